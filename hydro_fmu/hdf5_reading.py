"""Reading HDF5 files that someone else wrote: every link, group and dataset checked before use.

A database from elsewhere can be damaged or hostile in ways h5py only reports by raising whatever
its C library says (``KeyError: Unable to synchronously open object``, ``wrong B-tree
signature``). :class:`CheckedFile` wraps an open file and turns each way into one message naming
the file, the object and what to do:

* links: hard links and soft links that resolve inside the file are followed; an **external link**
  (data kept in another file, which may be missing or be anything) is refused, and a soft link
  that does not resolve (a missing target, a loop such as a link to itself) is named;
* objects: a missing group or dataset, or an object of the wrong kind (a dataset where a group
  belongs), named by its full path;
* datasets: the element type is checked (numbers, or text where text belongs: ``rho`` stored as
  the text ``"water"`` is refused, ``"inf"`` for a water depth is read) and the **declared size
  is checked before a byte is read**, against the size the layout expects and against
  :data:`MAX_DATASET_BYTES` (a damaged header can declare terabytes; reading it would end in
  ``MemoryError`` without naming the file);
* damaged bytes: HDF5's own errors while opening or reading an object (junk in the middle of the
  file) become one message naming the file and the object being read (:meth:`CheckedFile.guard`).
"""

from __future__ import annotations

import contextlib
import math
from collections.abc import Iterator
from pathlib import Path

import h5py
import numpy as np

MAX_DATASET_BYTES = 2**30  # one dataset of a hydrodynamic database; the largest bundled one holds 0.6 MB

# h5py's and HDF5's errors for a damaged file, a missing object or an unresolvable link
HDF5_ERRORS = (OSError, RuntimeError, KeyError, ValueError, TypeError)


class CheckedFile:
    """Checked access to the objects of an open HDF5 file.

    Args:
        f: the open file.
        path: its path, for messages.
        layout: what the file should be, for messages (e.g. ``"a BEMIO hydrodynamic database"``).
        error: the exception class raised (its constructor takes the message).
        fix: what the user should do, appended to every message.
    """

    def __init__(self, f: h5py.File, path: Path, layout: str, error: type[Exception],
                 fix: str = "write the file again with its original tool") -> None:
        self.f, self.path, self.layout, self.error, self.fix = f, Path(path), layout, error, fix
        self.where = "/"  # the object being read, for the message of an unexpected HDF5 error

    def fail(self, what: str) -> Exception:
        return self.error(f"{self.path}: {what}; {self.fix}")

    @contextlib.contextmanager
    def guard(self) -> Iterator[None]:
        """Turn any HDF5 error inside the block into one message naming the file and the object last
        opened (junk bytes in the file, an object h5py cannot decode)."""
        try:
            yield
        except self.error:
            raise
        except MemoryError:
            raise self.fail(f"reading {self.where} needs more memory than this machine has") from None
        except HDF5_ERRORS as exc:
            reason = " ".join(str(exc).split()) or type(exc).__name__
            raise self.fail(f"{self.layout} that cannot be read at {self.where}: the file is damaged or not in "
                            f"the expected layout (HDF5: {reason})") from None

    # ------------------------------------------------------------------------------------------- objects
    def _name(self, parent: h5py.Group, key: str) -> str:
        return f"{parent.name.rstrip('/')}/{key}"

    def _link(self, parent: h5py.Group, key: str) -> object | None:
        """The link ``key`` in ``parent`` (None if there is none), refusing external links."""
        name = self._name(parent, key)
        self.where = name
        link = parent.get(key, getlink=True)
        if isinstance(link, h5py.ExternalLink):
            raise self.fail(f"{name} is an external link to {link.filename}:{link.path}; the file must hold its "
                            "data itself (external links can point to a file that is missing or to anything)")
        return link

    def has(self, parent: h5py.Group, key: str) -> bool:
        """Whether ``parent`` holds an object ``key`` (a link that does not resolve is an error, not absence)."""
        return self._link(parent, key) is not None

    def _object(self, parent: h5py.Group, key: str, kind: type, what: str) -> h5py.Group | h5py.Dataset:
        name = self._name(parent, key)
        link = self._link(parent, key)
        if link is None:
            raise self.fail(f"{name} is missing ({what} of {self.layout})")
        try:
            obj = parent[key]
        except HDF5_ERRORS as exc:
            if isinstance(link, h5py.SoftLink):
                raise self.fail(f"{name} is a link to {link.path}, which does not resolve (a missing object or a "
                                "loop of links)") from None
            raise self.fail(f"{name} cannot be opened (HDF5: {' '.join(str(exc).split())}); the file is "
                            "damaged") from None
        if not isinstance(obj, kind):
            found = "a group" if isinstance(obj, h5py.Group) else "a dataset"
            raise self.fail(f"{name} is {found}, expected {what} ({self.layout})")
        return obj

    def group(self, parent: h5py.Group, key: str) -> h5py.Group:
        """The group ``key`` of ``parent``."""
        return self._object(parent, key, h5py.Group, "a group")

    def dataset(self, parent: h5py.Group, key: str) -> h5py.Dataset:
        """The dataset ``key`` of ``parent``, unread."""
        return self._object(parent, key, h5py.Dataset, "a dataset")

    # ------------------------------------------------------------------------------------------- values
    def numbers(self, parent: h5py.Group, key: str, size: int | None = None) -> np.ndarray:
        """A numeric dataset as float64, its type and declared size checked before it is read (``size``: the
        number of values the layout expects, if known)."""
        ds = self.dataset(parent, key)
        name = ds.name
        if ds.dtype.kind not in "fiub":
            if ds.dtype.kind in "SUO" and ds.size == 1:
                return np.array([self._number_text(ds)])
            raise self.fail(f"{name} holds {_kind(ds.dtype)}, expected numbers")
        self._check_size(ds, size)
        with self.guard():
            value = np.asarray(ds[()], dtype=float)
        return value

    def scalar(self, parent: h5py.Group, key: str) -> float:
        """A number stored as a one-value dataset (or as text such as ``"inf"``, as MATLAB writers leave it)."""
        value = self.numbers(parent, key)
        if value.size != 1:
            raise self.fail(f"{value.size} values in {self._name(parent, key)}, expected one number")
        return float(value.ravel()[0])

    def text(self, parent: h5py.Group, key: str) -> str:
        """A one-value text dataset (numbers are turned into their text)."""
        ds = self.dataset(parent, key)
        if ds.size != 1:
            raise self.fail(f"{ds.name} holds {ds.size} values, expected one text")
        if ds.dtype.kind not in "SUOfiu":
            raise self.fail(f"{ds.name} holds {_kind(ds.dtype)}, expected text")
        with self.guard():
            raw = np.asarray(ds[()]).ravel()[0]
        if isinstance(raw, bytes):
            try:
                return raw.decode()
            except UnicodeDecodeError:
                raise self.fail(f"{ds.name} is not UTF-8 text") from None
        return str(raw)

    def _number_text(self, ds: h5py.Dataset) -> float:
        with self.guard():
            raw = np.asarray(ds[()]).ravel()[0]
        text = raw.decode(errors="replace") if isinstance(raw, bytes) else str(raw)
        if text.strip().lower() in ("inf", "infinite", "infinity"):
            return math.inf
        try:
            return float(text)
        except ValueError:
            raise self.fail(f"{ds.name} is the text {text[:40]!r}, expected a number") from None

    def _check_size(self, ds: h5py.Dataset, size: int | None) -> None:
        declared = int(np.prod(ds.shape, dtype=object)) if ds.shape is not None else 0
        nbytes = declared * ds.dtype.itemsize
        if nbytes > MAX_DATASET_BYTES:
            raise self.fail(f"{ds.name} declares shape {ds.shape} ({nbytes / 1e9:.3g} GB), more than the "
                            f"{MAX_DATASET_BYTES / 2**30:g} GiB a dataset of {self.layout} may hold; the file is "
                            "damaged or not what it claims to be")
        if size is not None and declared != size:
            raise self.fail(f"{ds.name} has shape {ds.shape} ({declared} values), expected {size} values "
                            f"({self.layout})")


def _kind(dtype: np.dtype) -> str:
    if dtype.kind in "SUO":
        return "text"
    if dtype.kind == "V":
        return "compound or opaque data"
    if dtype.kind == "c":
        return "complex numbers"
    return f"data of type {dtype}"
