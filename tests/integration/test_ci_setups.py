"""The README's CI set-ups run as written: the GitHub workflow through the composite action (``action.yml``, its
bash steps run as a script the way the runner does), the GitLab job (its script lines, its Code Quality
artifact) and the pre-commit hook (run the way pre-commit runs a hook: the staged files its ``files`` pattern
selects, passed to its entry with the config's args). Each set-up is extracted from README.md, not copied here.

Offline: ``cadartifact`` on PATH is this checkout's package (a shim), the action's install step is turned off
(``install: false``), pip lines naming the placeholder host are left out. The pre-commit hook runs twice: as
:func:`run_hook` (pre-commit's file selection, spelled out) and through pre-commit itself, whose hook virtualenv
is built offline (no index, no dependencies: it finds them on the test environment's site-packages).
"""

import json
import os
import re
import shlex
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from cadartifact.testing.paths import ROOT, SAMPLES

yaml = pytest.importorskip("yaml")
pytest.importorskip("OCP")

pytestmark = pytest.mark.slow


def readme_yaml(first_line: str) -> dict:
    """The README's YAML block whose first line is ``first_line``."""
    blocks = re.findall(r"```yaml\n(.*?)```", (ROOT / "README.md").read_text(), re.S)
    (block,) = [b for b in blocks if b.splitlines()[0].strip() == first_line]
    return yaml.safe_load(block)


@pytest.fixture
def checkout(tmp_path):
    """A repository's checkout: models/ with a panel that passes at 0.05 mm and one that fails; ``cadartifact``
    on PATH runs this checkout's package."""
    work = tmp_path / "repo"
    (work / "models").mkdir(parents=True)
    for name in ("clean_panel.step", "wavy_panel_diagonal.step"):
        shutil.copy(SAMPLES / name, work / "models" / name)
    bin_dir = tmp_path / "bin"
    bin_dir.mkdir()
    shim = bin_dir / "cadartifact"
    shim.write_text(f'#!/bin/sh\nexec "{sys.executable}" -m cadartifact.cli "$@"\n')
    shim.chmod(0o755)
    env = dict(os.environ, PATH=f"{bin_dir}{os.pathsep}{os.environ['PATH']}", PYTHONPATH=str(ROOT),
               CADARTIFACT_WORKERS="1")
    env.pop("COLUMNS", None)
    return work, env


# ---------------------------------------------------------------- GitHub: the composite action
def _value(name: str, ctx: dict):
    name = name.strip()
    if name.startswith("hashFiles("):
        path = _value(name[len("hashFiles("):-1], ctx)
        return "hash" if (ctx["cwd"] / path).is_file() else ""
    if name.startswith("'"):
        return name.strip("'")
    scope, _, key = name.partition(".")
    if scope == "inputs":
        return ctx["inputs"][key]
    if scope == "github":
        return ctx["github"][key]
    if scope == "steps":
        step, _, output = key.partition(".outputs.")
        return ctx["steps"][step][output]
    raise AssertionError(f"an expression this runner does not know: {name}")


def condition(text: str, ctx: dict) -> bool:
    """A step's ``if:`` (the forms action.yml uses: ``always()``, ``==``/``!=`` and ``&&``)."""
    out = True
    for part in text.split("&&"):
        part = part.strip()
        if part == "always()":
            continue
        m = re.fullmatch(r"(.+?)\s*(==|!=)\s*(.+)", part)
        assert m, part
        equal = _value(m[1], ctx) == _value(m[3], ctx)
        out = out and (equal if m[2] == "==" else not equal)
    return out


def expand(text: str, ctx: dict) -> str:
    return re.sub(r"\$\{\{(.*?)\}\}", lambda m: str(_value(m[1], ctx)), text)


def run_action(cwd: Path, env: dict, given: dict, tmp_path: Path):
    """Run action.yml's steps as the runner does: inputs (defaults, then ``given``), each step's ``if``, bash
    steps with ``bash --noprofile --norc -eo pipefail``, ``$GITHUB_OUTPUT``; ``uses`` steps are recorded."""
    action = yaml.safe_load((ROOT / "action.yml").read_text())
    inputs = {k: str(v.get("default", "")) for k, v in action["inputs"].items()}
    unknown = set(given) - set(inputs)
    assert not unknown, unknown
    inputs.update({k: str(v) for k, v in given.items()})
    ctx = {"inputs": inputs, "github": {"action_path": str(ROOT)}, "steps": {}, "cwd": cwd}
    used, code = [], 0
    for step in action["runs"]["steps"]:
        if "if" in step and not condition(step["if"], ctx):
            continue
        if "uses" in step:
            used.append((step["uses"], {k: expand(str(v), ctx) for k, v in step.get("with", {}).items()}))
            continue
        out = tmp_path / f"output-{len(ctx['steps'])}"
        out.write_text("")
        step_env = dict(env, GITHUB_OUTPUT=str(out), **{k: expand(str(v), ctx) for k, v in step.get("env", {}).items()})
        res = subprocess.run(["bash", "--noprofile", "--norc", "-eo", "pipefail", "-c", expand(step["run"], ctx)],
                             cwd=cwd, env=step_env, capture_output=True, text=True, timeout=600)
        assert "Traceback" not in res.stderr, res.stderr[-2000:]
        ctx["steps"][step.get("id", f"step{len(ctx['steps'])}")] = dict(
            line.split("=", 1) for line in out.read_text().splitlines() if "=" in line)
        code = res.returncode
        if code:
            break  # the job fails here
    return code, used, ctx


def test_the_readme_github_workflow_runs_through_the_action(checkout, tmp_path):
    work, env = checkout
    workflow = readme_yaml("# .github/workflows/cad-quality.yml")
    steps = workflow["jobs"]["gate"]["steps"]
    (ours,) = [s for s in steps if s.get("uses", "").startswith("your-org/cadartifact@")]
    assert workflow["jobs"]["gate"]["permissions"]["security-events"] == "write"
    code, used, ctx = run_action(work, env, dict(ours["with"], install="false"), tmp_path)
    assert code == 1  # the wavy panel fails at 0.05 mm: the job fails, after the upload
    assert ctx["steps"]["gate"]["exit-code"] == "1"
    assert used == [("github/codeql-action/upload-sarif@v3", {"sarif_file": "cadartifact.sarif"})]
    log = json.loads((work / "cadartifact.sarif").read_text())
    uris = {r["locations"][0]["physicalLocation"]["artifactLocation"]["uri"] for r in log["runs"][0]["results"]}
    assert uris == {"models/wavy_panel_diagonal.step"}
    # the install step installs the action's own checkout
    action = yaml.safe_load((ROOT / "action.yml").read_text())
    assert "${{ github.action_path }}" in action["runs"]["steps"][0]["run"]


def test_the_action_passes_a_clean_vault_and_uses_a_baseline(checkout, tmp_path):
    work, env = checkout
    code, used, _ = run_action(work, env, {"paths": "models/clean_panel.step", "tolerance": "0.05",
                                           "install": "false"}, tmp_path)
    assert code == 0 and used  # SARIF uploaded
    subprocess.run(["cadartifact", "gate", "models", "--tol", "0.05", "--baseline", "base.json",
                    "--update-baseline"], cwd=work, env=env, check=True, capture_output=True)
    code, used, ctx = run_action(work, env, {"paths": "models", "tolerance": "0.05", "baseline": "base.json",
                                             "format": "gitlab", "output": "gl.json", "install": "false"}, tmp_path)
    assert code == 0 and ctx["steps"]["gate"]["exit-code"] == "0" and used == []  # no SARIF: no upload
    assert json.loads((work / "gl.json").read_text())[0]["location"]["path"] == "models/wavy_panel_diagonal.step"


def test_a_usage_error_fails_the_action_without_an_upload(checkout, tmp_path):
    work, env = checkout
    code, used, ctx = run_action(work, env, {"paths": "models", "install": "false"}, tmp_path)  # no tolerance
    assert code == 2 and ctx["steps"]["gate"]["exit-code"] == "2" and used == []


# ---------------------------------------------------------------- GitLab: Code Quality
def test_the_readme_gitlab_job_writes_its_code_quality_report(checkout):
    work, env = checkout
    job = readme_yaml("# .gitlab-ci.yml")["cad-quality"]
    report = job["artifacts"]["reports"]["codequality"]
    assert job["artifacts"]["when"] == "always"  # the report also when the gate fails
    lines = [line for line in job["script"] if "your-org" not in line]
    assert len(lines) == len(job["script"]) - 1 and lines[0].startswith("cadartifact gate")
    res = subprocess.run(["bash", "-eo", "pipefail", "-c", "\n".join(lines)], cwd=work, env=env,
                         capture_output=True, text=True, timeout=600)
    assert res.returncode == 1, res.stderr[-2000:]
    issues = json.loads((work / report).read_text())
    assert [(i["check_name"], i["severity"], i["location"]["path"]) for i in issues] == [
        ("CA001-ripple-exceeds-tolerance", "major", "models/wavy_panel_diagonal.step")]
    assert re.fullmatch(r"[0-9a-f]{32}", issues[0]["fingerprint"]) and issues[0]["location"]["lines"]["begin"] > 1


# ---------------------------------------------------------------- pre-commit
def run_hook(repo: Path, env: dict, config: dict) -> int:
    """Run the config's cadartifact hook as pre-commit does: the hook's definition (.pre-commit-hooks.yaml) with
    the config's overrides, the staged files its ``files`` pattern finds (``re.search``), passed after the
    entry and args in one call (``require_serial``)."""
    (repo_cfg,) = [r for r in config["repos"] if r["repo"].endswith("/cadartifact")]
    (hook_cfg,) = repo_cfg["hooks"]
    (hook,) = [h for h in yaml.safe_load((ROOT / ".pre-commit-hooks.yaml").read_text()) if h["id"] == hook_cfg["id"]]
    hook = dict(hook, **hook_cfg)
    assert hook["language"] == "python" and hook["pass_filenames"] and hook["require_serial"]
    staged = subprocess.run(["git", "diff", "--cached", "--name-only", "-z"], cwd=repo, env=env, check=True,
                            capture_output=True, text=True).stdout.split("\0")
    files = [f for f in staged if f and re.search(hook["files"], f)]
    if not files:
        return 0  # pre-commit skips a hook with no file
    res = subprocess.run([*shlex.split(hook["entry"]), *map(str, hook.get("args", [])), *files], cwd=repo, env=env,
                         capture_output=True, text=True, timeout=600)
    assert "Traceback" not in res.stderr, res.stderr[-2000:]
    return res.returncode


def test_the_readme_pre_commit_hook_checks_the_staged_models(checkout):
    work, env = checkout
    config = readme_yaml("repos:")
    env = dict(env, GIT_AUTHOR_NAME="t", GIT_AUTHOR_EMAIL="t@t", GIT_COMMITTER_NAME="t", GIT_COMMITTER_EMAIL="t@t")
    subprocess.run(["git", "init", "-q"], cwd=work, env=env, check=True)
    (work / "notes.md").write_text("not a model\n")
    subprocess.run(["git", "add", "notes.md", "models/clean_panel.step"], cwd=work, env=env, check=True)
    assert run_hook(work, env, config) == 0
    subprocess.run(["git", "add", "models/wavy_panel_diagonal.step"], cwd=work, env=env, check=True)
    assert run_hook(work, env, config) == 1
    subprocess.run(["git", "rm", "-q", "--cached", "models/clean_panel.step", "models/wavy_panel_diagonal.step"],
                   cwd=work, env=env, check=True)
    assert run_hook(work, env, config) == 0  # only notes.md: the hook does not run


def test_pre_commit_itself_runs_the_readme_config(checkout, tmp_path):
    """pre-commit itself (not a stand-in) runs the README's config on this checkout's hook, offline: its
    virtualenv gets this checkout installed without dependencies or an index, and finds numpy, OCP and the rest
    on the test environment's own site-packages."""
    pytest.importorskip("pre_commit")
    import sysconfig

    head = subprocess.run(["git", "rev-parse", "HEAD"], cwd=ROOT, capture_output=True, text=True)
    if head.returncode:
        pytest.skip(f"{ROOT} is not a git checkout: pre-commit clones the hook's repository")
    work, env = checkout
    config = readme_yaml("repos:")
    config["repos"][0].update(repo=str(ROOT), rev=head.stdout.strip())
    (work / ".pre-commit-config.yaml").write_text(yaml.safe_dump(config))
    env = dict(env, GIT_AUTHOR_NAME="t", GIT_AUTHOR_EMAIL="t@t", GIT_COMMITTER_NAME="t", GIT_COMMITTER_EMAIL="t@t",
               PRE_COMMIT_HOME=str(tmp_path / "pre-commit-home"), PIP_NO_INDEX="1", PIP_NO_DEPS="1",
               PIP_NO_BUILD_ISOLATION="0", VIRTUALENV_NO_PERIODIC_UPDATE="1",
               PYTHONPATH=sysconfig.get_paths()["purelib"])
    subprocess.run(["git", "init", "-q"], cwd=work, env=env, check=True)
    subprocess.run(["git", "add", ".pre-commit-config.yaml", "models/clean_panel.step"], cwd=work, env=env,
                   check=True)

    def pre_commit() -> subprocess.CompletedProcess:
        return subprocess.run([sys.executable, "-m", "pre_commit", "run"], cwd=work, env=env, capture_output=True,
                              text=True, timeout=600)

    clean = pre_commit()
    assert clean.returncode == 0, clean.stdout[-2000:]
    assert "cadartifact gate" in clean.stdout and "Passed" in clean.stdout
    subprocess.run(["git", "add", "models/wavy_panel_diagonal.step"], cwd=work, env=env, check=True)
    wavy = pre_commit()
    assert wavy.returncode == 1, wavy.stdout[-2000:]
    assert "Failed" in wavy.stdout and "wavy_panel_diagonal.step" in wavy.stdout
    assert "Traceback" not in wavy.stdout
