"""The gate's result cache (``cadartifact gate --cache DIR``): incremental by content.

A file's gate entry is stored under a key made of the SHA-256 of the file's bytes, the effective
policy of that file (its :class:`~cadartifact.gate.policy.FileSettings`, ``advise`` included, and ``--verify``, in a
canonical JSON serialisation), the cadartifact version and the gate schema. An unchanged file under
an unchanged policy is therefore not analysed again; a changed byte, setting or version is a new
key, hence a miss. The file's path is not part of the key: an identical copy elsewhere is a hit, and
its entry is relocated to the new path (every string that names the old path, i.e. the ``path`` and
the ``"<path>: ..."`` messages; an entry naming the old path in any other way is not reused).

Layout: one file per key, ``DIR/<key[:2]>/<key>.json`` (a JSON header line with the format, key,
path and checksum, then the entry as JSON), written to a temporary file in the
same folder and moved into place with ``os.replace``, so concurrent writers (two CI jobs, a Dask
client on each of several machines sharing the folder) never expose a partial entry: the last
writer of a key wins, and every writer of a key writes the same result. Each entry carries a
SHA-256 of its key, path and body; an entry that does not parse, names another key, or fails its checksum
is ignored (a miss) and rewritten after the analysis, never trusted.

Error entries (unreadable files, crashed workers) are never stored: a file the gate could not read
is read again on every run, so that the gate fails closed on fresh evidence.
"""

from __future__ import annotations

import hashlib
import json
import os
import tempfile
from pathlib import Path

from ..errors import InputError

__all__ = ["CACHE_FORMAT", "GateCache", "cache_key", "file_digest"]

CACHE_FORMAT = "cadartifact.gate.run-cache/1"

_UMASK = os.umask(0)
os.umask(_UMASK)


def _canonical(obj) -> str:
    """Canonical JSON: sorted keys, no spaces, strict floats (repr round-trips exactly)."""
    return json.dumps(obj, sort_keys=True, separators=(",", ":"), allow_nan=False, ensure_ascii=True)


def _ordered(obj) -> str:
    """JSON keeping the key order (the reports follow the entry's order), as stored in the cache."""
    return json.dumps(obj, separators=(",", ":"), allow_nan=False, ensure_ascii=True)


def file_digest(path) -> str:
    """SHA-256 (hex) of a file's bytes.

    Raises
    ------
    OSError
        The file cannot be read.
    """
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


#: Revision of the analysis a cached record came from: raised when the numbers a file gets change while the
#: version does not (development builds), so an older build's records are not served.
ANALYSIS_REVISION = 9  # 2: homogeneous rational faces, junctions, canonical faces (issue 10); 3: repeated faces;
#                        4: the intent's uncertainty and the decision rule (issue 22); 5: PDQ criteria (issue 25); 6: a cage's
#                        extraordinary vertices (issue 41); 7: the net reading's U of today's value sharper
#                        than a candidate's (issue 39); 8: the surface reading's candidates carry their own U;
#                        9: the advised net's own ripple carries the U the gate decides it by


def cache_key(digest: str, settings, verify: bool, reuse: bool = True) -> str:
    """The cache key of one file: SHA-256 over its digest, policy, ``verify``, version, schema,
    :data:`ANALYSIS_REVISION` and whether repeated faces reuse their first face's analysis.

    Parameters
    ----------
    digest : str
        :func:`file_digest` of the file.
    settings : FileSettings
        The file's effective settings.
    verify : bool
    reuse : bool
        Repeated faces reuse their first face's analysis (the run's ``reuse_faces``).
    """
    from .. import __version__
    from .run import GATE_SCHEMA

    # repeats reuse their first face's record (a note, last bits) unless the run's reuse_faces is off
    text = _canonical({"content": digest, "policy": settings.to_dict(), "verify": bool(verify),
                       "version": __version__, "schema": GATE_SCHEMA, "analysis": ANALYSIS_REVISION,
                       "reuse": bool(reuse)})
    return hashlib.sha256(text.encode()).hexdigest()


def _checksum(key: str, path: str, body: bytes) -> str:
    return hashlib.sha256(key.encode() + b"\0" + path.encode("utf-8", "surrogatepass") + b"\0" + body).hexdigest()


class _NotRelocatable(Exception):
    pass


def relocate(obj, old: str, new: str):
    """``obj`` (JSON-like) with the path ``old`` replaced by ``new`` in the strings that name it.

    A string equal to ``old`` or starting with ``old + ":"`` is rewritten; any other string that
    contains ``old`` raises :class:`_NotRelocatable` (the entry would be ambiguous).
    """
    if old == new:
        return obj
    if isinstance(obj, str):
        if obj == old:
            return new
        if obj.startswith(old + ":"):
            return new + obj[len(old):]
        if old in obj:
            raise _NotRelocatable(obj)
        return obj
    if isinstance(obj, dict):
        return {k: relocate(v, old, new) for k, v in obj.items()}
    if isinstance(obj, list):
        return [relocate(v, old, new) for v in obj]
    return obj


class GateCache:
    """A folder of cached gate entries (see the module docstring).

    Parameters
    ----------
    folder : path-like
        Created if missing.

    Raises
    ------
    InputError
        The folder cannot be created or is not a folder.
    """

    def __init__(self, folder):
        self.folder = Path(folder)
        try:
            self.folder.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise InputError(self.folder, f"cannot use as the gate cache ({exc.strerror or exc})") from None
        if not self.folder.is_dir():
            raise InputError(self.folder, "cannot use as the gate cache: not a folder")
        self.hits = self.misses = self.rejected = 0

    def _file(self, key: str) -> Path:
        return self.folder / key[:2] / f"{key}.json"

    def load(self, key: str, path: str):
        """The entry stored under ``key``, relocated to ``path``; None on a miss or an invalid entry."""
        try:
            raw = self._file(key).read_bytes()
        except OSError:
            return None
        try:
            head, sep, body = raw.partition(b"\n")
            if not sep:
                raise ValueError("no header line")
            meta = json.loads(head)
            valid = (isinstance(meta, dict) and meta.get("format") == CACHE_FORMAT and meta.get("key") == key
                     and isinstance(meta.get("path"), str)
                     and meta.get("sha256") == _checksum(key, meta["path"], body))
            if not valid:
                raise ValueError("invalid entry")
            entry = json.loads(body)
            if not isinstance(entry, dict):
                raise ValueError("invalid entry")
            return relocate(entry, meta["path"], path)
        except (ValueError, TypeError, _NotRelocatable, RecursionError):  # UnicodeDecodeError is a ValueError
            self.rejected += 1
            return None

    def store(self, key: str, entry: dict) -> bool:
        """Write ``entry`` under ``key`` atomically; False (and nothing written) for an error entry or a failed write.

        A cache that cannot be written is not an error of the gate: the entry is simply not cached.
        The file is a header line (format, key, path, SHA-256 of key, path and body) and the body,
        the entry as JSON in its own key order (the reports follow it).
        """
        if entry.get("error") or entry.get("verdict") == "error":
            return False
        try:
            body = _ordered(entry).encode("ascii")
            path = entry["path"]
            head = _ordered({"format": CACHE_FORMAT, "key": key, "path": path,
                             "sha256": _checksum(key, path, body)}).encode("ascii")
        except (TypeError, ValueError, KeyError):  # not JSON-representable: never cache what cannot round-trip
            return False
        target = self._file(key)
        tmp = None
        try:
            target.parent.mkdir(exist_ok=True)
            fd, tmp = tempfile.mkstemp(dir=target.parent, prefix=f".{key[:16]}.", suffix=".tmp")
            with os.fdopen(fd, "wb") as fh:
                fh.write(head + b"\n" + body)
            os.chmod(tmp, 0o666 & ~_UMASK)  # mkstemp makes it private; the cache may be shared
            os.replace(tmp, target)
            return True
        except OSError:
            if tmp is not None:
                try:
                    os.unlink(tmp)
                except OSError:
                    pass
            return False

    def run(self, tasks: list, execute, done, reuse: bool = True) -> list:
        """Gate ``tasks`` (``(path, settings, verify)``), analysing only the misses.

        Parameters
        ----------
        tasks : list of tuple
        execute : callable
            ``execute(tasks, done) -> entries`` runs the misses (in this process, a pool or a cluster).
        done : callable
            ``done(entry, cached=...)`` after each file.
        reuse : bool
            The run reuses repeated faces' analysis (the run's ``reuse_faces``): part of the key.

        Returns
        -------
        list of dict
            Entries in input order. Every entry is normalised through JSON (lists, not tuples), so a
            cold and a warm run give the same documents byte for byte.
        """
        results: list = [None] * len(tasks)
        keys: list = [None] * len(tasks)
        todo = []
        for i, (path, settings, verify) in enumerate(tasks):
            keys[i] = _key_or_none(path, settings, verify, reuse)  # None: unreadable, the analysis reports it
            entry = self.load(keys[i], path) if keys[i] else None
            if entry is None:
                todo.append(i)
                continue
            self.hits += 1
            results[i] = entry
            done(entry, cached=True)
        self.misses += len(todo)

        def finished(entry):
            done(entry, cached=False)

        fresh = execute([tasks[i] for i in todo], finished) if todo else []
        for i, entry in zip(todo, fresh):
            try:
                entry = json.loads(json.dumps(entry, allow_nan=False))
            except (TypeError, ValueError):
                pass  # not JSON-representable: kept as is, and store() refuses it
            path, settings, verify = tasks[i]
            # a file rewritten while it was analysed must not file the new result under the old bytes
            if keys[i] and keys[i] == _key_or_none(path, settings, verify, reuse):
                self.store(keys[i], entry)
            results[i] = entry
        return results


def _key_or_none(path, settings, verify, reuse=True):
    try:
        return cache_key(file_digest(path), settings, verify, reuse)
    except OSError:
        return None
