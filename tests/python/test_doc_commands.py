"""Every command in the documentation copy-pastes and runs.

The rules, for README.md and every guide (docs/, docs/notes/, python/, eval/, apps/*, config/sim,
fuzz/, bench/peers, dynamics/massid, bag2asl):

* every fenced block names its language: ``bash`` blocks are commands, ``text`` blocks are
  synopses, program output and diagrams (``yaml``, ``cmake``, ``python`` ... as they are);
* the ``bash`` blocks of one file run in order, as one script (``set -euo pipefail``) from the
  repository root, with ``build/bin`` and ``.venv/bin`` first on PATH (what the guides tell the
  reader to do) and ``CI=true``; a failing block fails the test naming file and line;
* a block may be skipped only with a reason on the line before it,
  ``<!-- doc-test: skip: REASON -->`` (an hour-long soak, a build of the peers, a cluster); the
  skipped blocks are listed in the test's output;
* ``scripts/test.sh`` and ``.ci/run`` lines are never run: they are the command that runs this
  test;
* every relative link resolves to a file or folder of the repository.
"""
from __future__ import annotations

import dataclasses
import os
import re
import subprocess
from pathlib import Path

import pytest

from conftest import REPO, build_dir

DOCS = sorted(
    {REPO / "README.md", REPO / "python" / "README.md", REPO / "eval" / "README.md",
     REPO / "config" / "sim" / "README.md", REPO / "fuzz" / "README.md", REPO / "bench" / "peers" / "README.md",
     REPO / "dynamics" / "massid" / "README.md", REPO / "eval" / "vid_eval" / "bag2asl" / "README.md",
     *(REPO / "docs").glob("*.md"), *(REPO / "docs" / "notes").glob("*.md"), *(REPO / "apps").glob("*/README.md")})
SKIP = re.compile(r"<!--\s*doc-test:\s*skip:\s*(.+?)\s*-->")
SELF = re.compile(r"(^|\s)(bash\s+)?(\./)?(scripts/test\.sh|\.ci/run)(\s|$)")


@dataclasses.dataclass
class Block:
    path: Path
    line: int  # 1-based line of the opening fence
    lang: str
    body: list
    skip: str | None

    @property
    def where(self) -> str:
        return f"{self.path.relative_to(REPO)}:{self.line}"


def blocks(path: Path) -> list:
    lines = path.read_text().split("\n")
    out, i = [], 0
    while i < len(lines):
        if lines[i].startswith("```"):
            j = i + 1
            while j < len(lines) and not lines[j].startswith("```"):
                j += 1
            prev = next((lines[k] for k in range(i - 1, -1, -1) if lines[k].strip()), "")
            m = SKIP.search(prev)
            out.append(Block(path, i + 1, lines[i][3:].strip(), lines[i + 1:j], m.group(1) if m else None))
            i = j + 1
        else:
            i += 1
    return out


def _ids(paths):
    return [str(p.relative_to(REPO)) for p in paths]


def test_the_documents_exist():
    assert REPO / "README.md" in DOCS and len(DOCS) >= 10


@pytest.mark.parametrize("path", DOCS, ids=_ids(DOCS))
def test_every_fence_names_its_language(path):
    bare = [b.where for b in blocks(path) if not b.lang]
    assert not bare, f"fenced blocks without a language (bash to run, text otherwise): {bare}"


@pytest.mark.parametrize("path", DOCS, ids=_ids(DOCS))
def test_relative_links_resolve(path):
    text = re.sub(r"```.*?```", "", path.read_text(), flags=re.S)  # links inside code are code
    broken = []
    for target in re.findall(r"\]\(([^)\s]+)\)", text):
        if re.match(r"[a-z]+://|mailto:|#", target):
            continue
        if not (path.parent / target.split("#")[0]).exists():
            broken.append(target)
    assert not broken, f"{path.relative_to(REPO)}: links to nothing: {broken}"


def _script(path: Path) -> tuple[str, list]:
    parts, skipped = ["set -euo pipefail"], []
    for b in blocks(path):
        if b.lang != "bash":
            continue
        if b.skip:
            skipped.append(f"{b.where} ({b.skip})")
            continue
        parts.append(f"echo '>>> doc block {b.where}' >&2")
        parts += [ln for ln in b.body if not SELF.search(ln)]
    return "\n".join(parts) + "\n", skipped


RUNNABLE = [p for p in DOCS if any(b.lang == "bash" and not b.skip for b in blocks(p))]


@pytest.mark.parametrize("path", RUNNABLE, ids=_ids(RUNNABLE))
def test_commands_run(path, tmp_path, capsys):
    script, skipped = _script(path)
    env = {**os.environ, "CI": "true",
           "PATH": f"{build_dir() / 'bin'}:{REPO / '.venv' / 'bin'}:{os.environ.get('PATH', '/usr/bin:/bin')}"}
    (tmp_path / "doc.sh").write_text(script)
    r = subprocess.run(["bash", str(tmp_path / "doc.sh")], cwd=REPO, env=env, capture_output=True, text=True,
                       timeout=1200)
    with capsys.disabled():
        for s in skipped:
            print(f"\n[doc-test] skipped {s}")
    last = [ln for ln in r.stderr.splitlines() if ln.startswith(">>> doc block")]
    assert r.returncode == 0, (f"{last[-1] if last else path} failed (exit {r.returncode}):\n"
                               f"{r.stdout[-3000:]}\n{r.stderr[-3000:]}")


def test_skips_carry_a_reason_and_mark_bash_blocks():
    skipped = [b for p in DOCS for b in blocks(p) if b.skip]
    assert all(len(b.skip) >= 20 for b in skipped), [b.where for b in skipped if len(b.skip) < 20]
    assert all(b.lang == "bash" for b in skipped), [b.where for b in skipped if b.lang != "bash"]
