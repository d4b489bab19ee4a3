"""The README as a front door, and module docstrings that describe the code (issue #38).

- README.md is at most 150 lines, none much wider than a screen;
- every path it names in the repository (``scripts/*.py``, ``docs/``, ``data/``, pictures...)
  exists, or is written by ``make demo`` (into ``results/``: the demo's own arguments, or a file
  that the job writing into one of its folders declares, `slicelab.tasks.JOBS`), or by
  ``make data-large`` (``data/large/``);
- every dependency of pyproject.toml is named in its section "Dependencies and why";
- neither the README nor a module docstring carries a benchmark diary: no "session", "this run",
  "was tried", and no timing figure ("0.3 s", "12 ms", "0.9x"). Measured figures belong to the
  performance pages of the docs, written by the scripts that measure them.

The checks are functions of text, and `test_the_checks_catch_what_they_are_for` feeds each one
text that must fail.
"""
from __future__ import annotations

import ast
import importlib.util
import re
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
README = ROOT / "README.md"
MAX_LINES = 150
MAX_WIDTH = 200

#: Subpackages whose module docstrings are not held to the rule (none: every module is).
NOT_YET = ()

DIARY = re.compile(r"\bsessions?\b|\bthis run\b|\bwas tried\b|\bnot kept\b|\btimed by hand\b",
                   re.IGNORECASE)
#: A duration ("0.3 s", "10-20 ms", "2 seconds") or a speed ratio ("0.9x", "1.5-2.3x"). Case matters:
#: "M204 S" in a G-code example is no duration, nor is "1h 2m 3s", PrusaSlicer's way of writing one.
TIMING = re.compile(r"\b\d+(?:\.\d+)?(?:\s*-\s*\d+(?:\.\d+)?)?\s+(?:s|ms|us|µs|seconds?|minutes?)\b"
                    r"|\b\d+(?:\.\d+)?(?:-\d+(?:\.\d+)?)?x\b")
#: A path in the repository, wherever the README names it (prose, links, code blocks).
REPO_PATH = re.compile(r"(?<![\w/.~-])((?:data|docs|scripts|tests|notebooks|results|slicelab)/[\w./*-]*)")


def _demo():
    spec = importlib.util.spec_from_file_location("slicelab_demo_script", ROOT / "scripts" / "demo.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


# ---- the checks, as functions of text ----------------------------------------------------------

def size_problems(text: str) -> list[str]:
    """Too many lines, or lines too wide."""
    lines = text.splitlines()
    problems = [f"{len(lines)} lines (at most {MAX_LINES})"] if len(lines) > MAX_LINES else []
    return problems + [f"line {i}: {len(line)} characters" for i, line in enumerate(lines, 1)
                       if len(line) > MAX_WIDTH]


def named_paths(text: str) -> list[str]:
    """The repository paths that `text` names, trailing punctuation left off."""
    return sorted({m.rstrip(".,;:)") for m in REPO_PATH.findall(text)})


def demo_outputs(results: Path) -> tuple[set[Path], dict[Path, set[str]]]:
    """What `make demo` writes into `results`: the paths its steps name, and for each folder
    named after ``-o`` or ``--preview`` the file names that its job declares."""
    from slicelab.tasks import JOBS
    paths, folders = set(), {}
    for _title, args, stdout_name in _demo().steps(results):
        if stdout_name:
            paths.add(results / stdout_name)
        for flag, value in zip(args, args[1:]):
            if flag in ("-o", "--png", "--json", "--preview", "--dxf", "--csv"):
                paths.add(Path(value))
                if flag in ("-o", "--preview") and not Path(value).suffix:
                    job = JOBS.get(args[0])  # a batch's folders hold a folder per input: none named here
                    folders[Path(value)] = set(job.outputs.values()) if job else set()
    return paths, folders


def missing_paths(text: str, root: Path = ROOT) -> list[str]:
    """Paths named in `text` that do not exist under `root` and that no make target writes."""
    results = root / "results"
    made, folders = demo_outputs(results)
    missing = []
    for name in named_paths(text):
        path = root / name
        if name.startswith("data/large/") or name == "data/large":
            ok = "data-large:" in (root / "Makefile").read_text()
        elif name.startswith("results/") or name == "results":
            ok = (path == results or path in made
                  or (path.parent in folders and path.name in folders[path.parent]))
        else:
            ok = path.exists() or ("*" in name and any(root.glob(name)))
        if not ok:
            missing.append(name)
    return missing


def section(text: str, heading: str) -> str:
    """The body of the ``## heading`` section of a Markdown text."""
    m = re.search(rf"^## {re.escape(heading)}\n(.*?)(?=^## |\Z)", text, re.MULTILINE | re.DOTALL)
    return m.group(1) if m else ""


def unnamed_dependencies(text: str, pyproject: dict) -> list[str]:
    """The dependencies of `pyproject` that the README's "Dependencies and why" does not name."""
    body = section(text, "Dependencies and why").lower()
    names = [re.match(r"[A-Za-z0-9_.-]+", d).group(0).lower() for d in pyproject["project"]["dependencies"]]
    return [n for n in names if not re.search(rf"(?<![\w-]){re.escape(n)}(?![\w-])", body)]


def diary_marks(text: str) -> list[str]:
    """Words of a benchmark diary and timing figures in `text`."""
    return [m.group(0) for m in DIARY.finditer(text)] + [m.group(0) for m in TIMING.finditer(text)]


def module_docstrings(root: Path = ROOT / "slicelab") -> dict[str, str]:
    """Each module's docstring, by its path, outside the subpackages of `NOT_YET`."""
    docs = {}
    for path in sorted(root.rglob("*.py")):
        rel = path.relative_to(root)
        if rel.parts[0] in NOT_YET:
            continue
        docs[str(rel)] = ast.get_docstring(ast.parse(path.read_text()), clean=False) or ""
    return docs


# ---- the README and the package -----------------------------------------------------------------

def test_the_readme_is_short():
    assert not size_problems(README.read_text())


def test_every_script_the_readme_names_exists():
    scripts = [p for p in named_paths(README.read_text()) if p.startswith("scripts/")]
    assert scripts, "the README names the scripts that print its figures"
    assert all(p.endswith(".py") and ((ROOT / p).is_file() or ("*" in p and any(ROOT.glob(p)))) for p in scripts), scripts


def test_every_path_and_picture_the_readme_names_exists_or_is_made():
    text = README.read_text()
    pictures = re.findall(r"!\[[^\]]*\]\(([^)\s]+)\)", text)
    assert len(pictures) >= 3, "a picture per audience"
    links = [t for t in re.findall(r"\]\(([^)\s]+)\)", text) if "://" not in t]
    assert all(REPO_PATH.fullmatch(t) for t in links), [t for t in links if not REPO_PATH.fullmatch(t)]
    assert not missing_paths(text)


def test_the_readme_names_every_dependency():
    pyproject = tomllib.loads((ROOT / "pyproject.toml").read_text())
    assert section(README.read_text(), "Dependencies and why")
    assert not unnamed_dependencies(README.read_text(), pyproject)


def test_the_readme_keeps_no_diary():
    assert not diary_marks(README.read_text())


@pytest.mark.parametrize("command", ["make demo", "make test", "pip install ."])
def test_the_readme_gives_the_commands(command):
    lines = README.read_text().splitlines()
    assert any(command in line for line in lines[:20]), command
    if command.startswith("make "):
        assert f"\n{command.split()[1]}:" in (ROOT / "Makefile").read_text()


def test_module_docstrings_describe_the_code():
    marks = {path: diary_marks(doc) for path, doc in module_docstrings().items()}
    assert not {path: m for path, m in marks.items() if m}


# ---- the checks can fail ------------------------------------------------------------------------

def test_the_checks_catch_what_they_are_for(tmp_path):
    assert size_problems("line\n" * (MAX_LINES + 1))
    assert size_problems("x" * (MAX_WIDTH + 1))
    assert not size_problems("line\n" * MAX_LINES)

    assert missing_paths("see `scripts/no_such_script.py`")
    assert missing_paths("![a picture](results/no_such_picture.png)")
    assert missing_paths("![a picture](results/pot_parts/no_such_name.png)")
    assert not missing_paths("![the exploded view](results/pot_parts/exploded.png) of `data/pot.stl`")

    pyproject = {"project": {"dependencies": ["numpy>=1.26", "numpy-stl>=3.1", "shapely>=2.1"]}}
    text = "## Dependencies and why\n\n- numpy: arrays\n- shapely: caps\n\n## Next\n\nnumpy-stl\n"
    assert unnamed_dependencies(text, pyproject) == ["numpy-stl"]

    for diary in ("That was the last run of its session.", "the bridge 0.38 -> 0.36 s", "Tried and not kept:",
                  "cost 0.2-0.25 s per command", "0.90x PrusaSlicer's wall time", "10-20 ms of each command"):
        assert diary_marks(diary), diary
    for plain in ("``; estimated printing time (normal mode) = 1h 2m 3s``", "M204 S1000", "a 4 x 4 matrix",
                  "layers of 0.2 mm", "--volume 80x80x80"):
        assert not diary_marks(plain), plain

    package = tmp_path / "slicelab"
    (package / "viz").mkdir(parents=True)
    (package / "timed.py").write_text('"""Loads in 0.3 s on this machine."""\n')
    (package / "viz" / "later.py").write_text('"""Draws in 0.3 s."""\n')
    docs = module_docstrings(package)
    assert sorted(docs) == ["timed.py", "viz/later.py"] and all(diary_marks(d) for d in docs.values())
