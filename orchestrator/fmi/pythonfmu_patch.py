"""Fix of PythonFMU 0.7.0's Linux binary: its interpreter state is released twice at unload.

Found here (``docs/design.md``, "Found in our dependencies"): the FMU library keeps the embedded
interpreter's state in a static ``std::shared_ptr<PyState>``. Its static initialiser registers the
shared pointer's destructor with ``__cxa_atexit``, and the library's ELF destructor
``onLibraryUnload`` calls ``finalizePythonInterpreter``, which assigns ``nullptr`` to the same
shared pointer. At ``dlclose`` or at process exit both run, in that order: the second release
decrements a counter inside the already freed control block, i.e. it writes into a free heap
chunk. Depending on where the allocator put that chunk, the process then aborts with
``free(): corrupted unsorted chunks``, ``corrupted double-linked list`` or a segmentation fault
(fmpy: 2 runs in 5; a C host: every run). In a C host the first release also makes PythonFMU's
worker thread call ``Py_Finalize``, and finalising an interpreter that imported scipy from a
non-main thread reads freed memory (scipy 1.17's ``_uarray`` module frees its exception type while
another module's dictionary still refers to it; valgrind shows it with the multibody FMU alone).

The fix replaces two ``jmp`` instructions by ``ret`` in the shipped binary: the static
initialiser's tail call that registers the destructor, and ``onLibraryUnload``'s tail call of
``finalizePythonInterpreter``. The interpreter state then lives until the process ends (it is
never released, so never twice) and PythonFMU never finalises Python: the host's own exit is all
that happens. Nothing else in the binary changes. The patch is applied only to the exact binary
it was derived from (SHA-256 below); any other build is left as it is and the builder says so.
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass


@dataclass(frozen=True)
class BinaryPatch:
    """Byte replacements at file offsets of one known binary."""

    sha256: str
    edits: tuple[tuple[int, bytes, bytes], ...]  # (offset, expected bytes, replacement)


# libpythonfmu-export.so of PythonFMU 0.7.0 (linux64), as copied into every FMU.
PYTHONFMU_070_LINUX = BinaryPatch(
    sha256="4be156a552c16f30eb4395805c59855d8d4086056d0f165442565f6c5fbac0c9",
    edits=(
        # _GLOBAL__sub_I_PySlaveInstance.cpp: "jmp __cxa_atexit" (registers ~shared_ptr<PyState>) -> ret
        (0x16F8B, bytes.fromhex("e960d6ffff"), bytes.fromhex("c3")),
        # onLibraryUnload(): "jmp finalizePythonInterpreter" -> ret
        (0x16F34, bytes.fromhex("e937dcffff"), bytes.fromhex("c3")),
    ),
)

PATCHES = (PYTHONFMU_070_LINUX,)


def patch_library(data: bytes) -> tuple[bytes, bool]:
    """``(patched bytes, True)`` for a known PythonFMU binary, ``(data, False)`` for any other."""
    digest = hashlib.sha256(data).hexdigest()
    for patch in PATCHES:
        if digest != patch.sha256:
            continue
        out = bytearray(data)
        for offset, expected, replacement in patch.edits:
            if bytes(out[offset:offset + len(expected)]) != expected:  # pragma: no cover - guarded by the hash
                raise RuntimeError(f"PythonFMU binary differs from the known build at offset {offset:#x}")
            out[offset:offset + len(replacement)] = replacement
        return bytes(out), True
    return data, False


def is_patched(data: bytes) -> bool:
    """True if ``data`` is the known PythonFMU binary with the fix applied."""
    for patch in PATCHES:
        candidate = bytearray(data)
        for offset, expected, replacement in patch.edits:
            if bytes(candidate[offset:offset + len(replacement)]) != replacement:
                break
            candidate[offset:offset + len(expected)] = expected
        else:
            return hashlib.sha256(bytes(candidate)).hexdigest() == patch.sha256
    return False
