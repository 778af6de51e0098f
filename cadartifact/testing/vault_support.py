"""Shared by the cache and cluster tests: a small file set and every report of a gate run as text."""

import re
import shutil
from pathlib import Path

from .paths import REALDATA, SAMPLES

#: Quick files (about a second each or less): the samples and the smallest real files.
SAMPLE_NAMES = ("cage.obj", "car_hood_coarse.step", "clean_panel.step", "hull_freeform.step")
REAL_NAMES = ("obj/catmark_xord_boundary.obj", "obj/catmark_xord_interior.obj", "step/MAINBODY_BACK.stp")

TOL = 0.05


def small_set(folder: Path, real: bool = True) -> list[Path]:
    """Copies of the quick samples, the small real files (when ../shared/realdata is there) and a broken STEP."""
    folder.mkdir(parents=True, exist_ok=True)
    files = []
    for name in SAMPLE_NAMES:
        files.append(Path(shutil.copy(SAMPLES / name, folder / name)))
    if real and REALDATA.is_dir():
        files += [REALDATA / rel for rel in REAL_NAMES if (REALDATA / rel).is_file()]  # read in place
    broken = folder / "broken.step"
    broken.write_text("ISO-10303-21;\nHEADER;\nthis is not a STEP file\n")
    files.append(broken)
    return files


def settings_for(files, tol=TOL):
    from cadartifact.gate.policy import Policy, check_cli

    policy = Policy(source=None)
    cli = check_cli({"tolerance": tol})
    return policy, cli, [policy.settings_for(f, cli) for f in files]


def documents(entries, policy, cli, cwd) -> dict:
    """Every report of a run as text: json, text, junit, sarif and the HTML page (its clock blanked)."""
    from cadartifact.gate.run import build_document
    from cadartifact.gate.policy import base_settings
    from cadartifact.gate.reports import to_json, to_junit, to_text
    from cadartifact.gate.sarif import to_sarif
    from cadartifact.viz.html import render_html

    doc = build_document(entries, base_settings(policy, cli), policy)
    html = render_html(doc, heatmaps=False, maps=False)
    return {"json": to_json(doc), "text": to_text(doc), "junit": to_junit(doc), "sarif": to_sarif(doc, cwd=str(cwd)),
            "html": re.sub(r"\d{4}-\d{2}-\d{2} \d{2}:\d{2}", "<date>", html)}
