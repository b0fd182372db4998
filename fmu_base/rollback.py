"""In-memory rollback of a physics model: save what a step can change, set it back, keep every object's identity.

An iterative master sets a multibody FMU back to the start of the step at every iteration. A deep copy of the model
(``copy.deepcopy``) allocates the whole object graph again and drops the objects derived from it (the compiled
plan of :mod:`mbd_fmu.fast`, rebuilt after a restore): about a millisecond per copy for a two-body scene, ten times
the step itself. :func:`snapshot` instead walks the graph once and keeps

* for every instance of a class of the project (``PACKAGES``): a shallow copy of its attribute dictionary;
* for every list and dictionary reached: a shallow copy of its items;
* for every writeable numpy array reached: a copy of its data,

and :func:`restore` writes them back into the same objects (attribute bindings first, then the lists' and
dictionaries' items, then the arrays' data in place), so the graph is again what it was, object for object, and
whatever refers to its objects (views, compiled plans, caches keyed by identity) stays valid. The snapshot is not
consumed: it can be restored again. Objects created after the snapshot are simply no longer referenced.

What it cannot see: state outside Python objects (a C library's own memory, e.g. MoorDyn's) and objects of other
packages that are changed in place through their own methods. :func:`snapshot` returns None when the graph holds
an instance of a project class with its own ``__deepcopy__`` (the marker of such state: it knows how to copy
itself), and the caller then deep-copies as before.
"""

from __future__ import annotations

from typing import Any

import numpy as np

PACKAGES = ("mbd_fmu", "fmu_base", "hydro_fmu", "plain_mbd_fmu")


class Walk:
    """The objects a walk of the graph found (owners: project instances; lists; dicts; writeable arrays), every
    walked edge (container, key, child) and each container's size: what a snapshot copies, and how to tell whether
    the graph still has that shape (:meth:`update`)."""

    def __init__(self) -> None:
        self.owners: list[Any] = []
        self.lists: list[list] = []
        self.dicts: list[dict] = []
        self.arrays: list[np.ndarray] = []
        self.edges: list[list] = []  # [container (a dict: attributes or a mapping; or a list), key, child]
        self.sizes: list[tuple[Any, int]] = []
        self.seen: set[int] = set()
        self.opaque = False  # the graph holds state this cannot restore
        self.base = 0  # objects found by the last full walk

    def count(self) -> int:
        return len(self.owners) + len(self.lists) + len(self.dicts) + len(self.arrays)

    def visit(self, root: Any) -> None:
        """Walk ``root``'s graph, skipping what this walk found already."""
        stack = [root]
        seen, edges, sizes = self.seen, self.edges, self.sizes
        while stack:
            obj = stack.pop()
            key = id(obj)
            if key in seen:
                continue
            seen.add(key)
            if isinstance(obj, np.ndarray):
                if obj.flags.writeable and obj.dtype != object:
                    self.arrays.append(obj)
                continue
            if isinstance(obj, list):
                self.lists.append(obj)
                sizes.append((obj, len(obj)))
                children = enumerate(obj)
            elif isinstance(obj, tuple):
                stack.extend(c for c in obj if not isinstance(c, _LEAVES))
                continue
            elif isinstance(obj, dict):
                self.dicts.append(obj)
                sizes.append((obj, len(obj)))
                children = obj.items()
            else:
                attributes = getattr(obj, "__dict__", None)
                if attributes is None or not _project(obj):
                    continue  # another package's object without attributes of ours (a factorisation): kept
                if "__deepcopy__" in type(obj).__dict__:
                    self.opaque = True  # state of its own (e.g. in a C library): only its own copy knows it
                    return
                self.owners.append(obj)
                sizes.append((attributes, len(attributes)))
                children = attributes.items()
                obj = attributes
            for k, child in children:
                if not isinstance(child, _LEAVES):
                    edges.append([obj, k, child])
                    stack.append(child)

    def update(self) -> bool:
        """Bring the walk up to the graph as it is now: walk the children that replaced walked ones (a step
        rebinds a few arrays); False if a container changed size or the walk holds too many dead objects (then
        walk again from the root)."""
        for container, size in self.sizes:
            if len(container) != size:
                return False
        fresh = []
        for edge in self.edges:
            container, key, child = edge
            now = container[key]
            if now is not child:
                edge[2] = now
                fresh.append(now)
        for child in fresh:
            if not isinstance(child, _LEAVES):
                self.visit(child)
        return not self.opaque and self.count() <= 2 * max(self.base, 1)


class Snapshot:
    """What :func:`snapshot` saved (see the module docstring) and the walk it came from."""

    __slots__ = ("walk", "owners", "lists", "dicts", "arrays")

    def __init__(self, walk: Walk) -> None:
        self.walk = walk
        self.owners = [dict(obj.__dict__) for obj in walk.owners]
        self.lists = [list(items) for items in walk.lists]
        self.dicts = [dict(mapping) for mapping in walk.dicts]
        self.arrays = [array.copy() for array in walk.arrays]


_LEAVES = (str, bytes, int, float, complex, bool, type(None), np.generic)


def _project(obj: Any) -> bool:
    return type(obj).__module__.partition(".")[0] in PACKAGES


def snapshot(root: Any, previous: Snapshot | None = None) -> Snapshot | None:
    """Everything reachable from ``root`` that a step may change (module docstring), or None if the graph holds
    state this cannot restore. ``previous``: an earlier snapshot of the same root, whose walk is brought up to date
    (:meth:`Walk.update`) instead of walking the whole graph again."""
    walk = previous.walk if previous is not None else None
    if walk is None or not walk.update():
        walk = Walk()
        walk.visit(root)
        walk.base = walk.count()
    if walk.opaque:
        return None
    return Snapshot(walk)


def restore(snap: Snapshot) -> None:
    """Set the graph back to ``snap`` (module docstring); ``snap`` stays valid for another restore. Objects the walk
    found after ``snap`` was taken (children that replaced walked ones later) are not in it and not touched."""
    walk = snap.walk
    for obj, attributes in zip(walk.owners, snap.owners, strict=False):  # the walk may have grown since
        d = obj.__dict__
        d.clear()
        d.update(attributes)
    for items, saved in zip(walk.lists, snap.lists, strict=False):
        items[:] = saved
    for mapping, saved in zip(walk.dicts, snap.dicts, strict=False):
        mapping.clear()
        mapping.update(saved)
    for array, data in zip(walk.arrays, snap.arrays, strict=False):
        array[...] = data
