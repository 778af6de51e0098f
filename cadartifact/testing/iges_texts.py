"""IGES texts for the IGES reference tests (tests/exchange/test_iges_refs.py) and benchmarks/time_limits.py: the
hood sample written by OCCT's IGES writer, its directory's entity types, and a record's parameter set in place.
"""

from __future__ import annotations

import re
import warnings
from pathlib import Path

from cadartifact.testing.paths import SAMPLES


def hood_as_iges(folder: Path, mode: int) -> str:
    """The hood sample written by OCCT's IGES writer (mode 0: faces, mode 1: B-rep): its text."""
    from OCP.IGESControl import IGESControl_Writer

    from cadartifact.exchange.load import read
    from cadartifact.exchange.occ import make_face

    path = folder / f"hood_{mode}.igs"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        writer = IGESControl_Writer("MM", mode)
        writer.AddShape(make_face(read(SAMPLES / "car_hood_coarse.step").nets[0]))
        writer.ComputeModel()
        assert writer.Write(str(path))
    return path.read_text(encoding="latin-1")


def directory(text: str) -> list[int]:
    """The entity type of each directory entry (D1, D3, ...)."""
    return [int(ln[:8]) for ln in text.split("\n") if len(ln) >= 73 and ln[72] == "D"][::2]


def set_parameter(text: str, d: int, index: int, value: str) -> str:
    """``text`` with parameter ``index`` (0 = the first after the entity type) of entity ``D<d>``'s record set to
    ``value``, in place on its line (the line's data columns must hold it)."""
    lines = text.split("\n")
    rows = [k for k, ln in enumerate(lines) if len(ln) >= 73 and ln[72] == "P" and int(ln[64:72]) == d]
    count = -1  # the entity type is parameter -1
    for k in rows:
        data = lines[k][:64]
        starts = [0] + [m.end() for m in re.finditer(r"[,;]", data)]
        for a in starts[:-1] if data.rstrip()[-1:] in ",;" else starts:
            if count == index:
                b = re.search(r"[,;]|$", data[a:]).start() + a
                new = (data[:a] + value + data[b:]).rstrip()
                assert len(new) <= 64, "the line cannot hold the value"
                lines[k] = new.ljust(64) + lines[k][64:]
                return "\n".join(lines)
            count += 1
    raise AssertionError(f"D{d} has no parameter {index}")
