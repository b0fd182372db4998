"""The documentation site: ``mkdocs build --strict`` (every warning an error: links, anchors, pages left out of the
navigation), the API page's code blocks run as they stand in a fresh process, the README links the site, and the
pages speak to users (no tracker or branch vocabulary, nothing outside the repository)."""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
DOCS = ROOT / "docs"
PAGES = sorted(DOCS.rglob("*.md"))


def test_the_site_builds_with_no_warning(tmp_path: Path) -> None:
    done = subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict", "--site-dir", str(tmp_path / "site")],
                          cwd=ROOT, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stdout + done.stderr
    assert "WARNING" not in done.stderr + done.stdout
    assert (tmp_path / "site" / "api" / "index.html").is_file()
    assert (tmp_path / "site" / "index.html").is_file()


def test_the_build_fails_on_a_broken_link(tmp_path: Path) -> None:
    """Strict mode is what catches broken links: a copy of the docs with one bad anchor does not build."""
    import shutil

    copy = tmp_path / "repo"
    shutil.copytree(DOCS, copy / "docs")
    shutil.copy(ROOT / "mkdocs.yml", copy / "mkdocs.yml")
    page = copy / "docs" / "api.md"
    page.write_text(page.read_text() + "\nSee [nowhere](results.md#no-such-section).\n")
    done = subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict", "--site-dir", str(tmp_path / "site")],
                          cwd=copy, capture_output=True, text=True, timeout=600)
    assert done.returncode != 0 and "no-such-section" in done.stdout + done.stderr


def code_blocks(page: Path) -> list[str]:
    return re.findall(r"```python\n(.*?)```", page.read_text(), flags=re.S)


def test_every_code_block_of_the_api_page_runs_in_a_fresh_process(tmp_path: Path) -> None:
    """Acceptance: a new user follows docs/api.md from the repository's folder: its Python blocks, in order, in one
    fresh interpreter (the scenarios linked in, the results written beside them)."""
    blocks = code_blocks(DOCS / "api.md")
    assert len(blocks) >= 10
    (tmp_path / "scenarios").symlink_to(ROOT / "scenarios")
    script = tmp_path / "api_page.py"
    script.write_text("\n".join(f"# --- block {i + 1}\n{block}" for i, block in enumerate(blocks)))
    env = dict(os.environ)
    done = subprocess.run([sys.executable, str(script)], cwd=tmp_path, capture_output=True, text=True, timeout=900,
                          env=env)
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-5000:]
    out = done.stdout
    assert "waves.height = -3.0, set in Python: must not be negative (got -3.0)" in out
    assert "changed in Python (simulation.duration" in out
    assert "steady state against the exact frequency-domain solution" in out
    assert (tmp_path / "results" / "cylinder.nc").is_file() and (tmp_path / "results" / "figures").is_dir()


def test_the_readme_links_the_site_and_the_api_page() -> None:
    text = (ROOT / "README.md").read_text()
    assert "](docs/index.md)" in text and "](docs/api.md)" in text and "mkdocs build" in text


@pytest.mark.parametrize("page", PAGES + [ROOT / "README.md"], ids=lambda p: str(p.relative_to(ROOT)))
def test_pages_speak_to_users(page: Path) -> None:
    """No tracker or branch vocabulary and no path outside the repository."""
    text = page.read_text()
    for pattern in (r"\bseed (paper )?0\d\d\b", r"\b[Ii]ssues? \d+\b", r"\bon main\b", r"\bxfail", r"\.\./shared",
                    r"DESIGN\.md", r"\bbranch (speed|main)"):
        found = re.search(pattern, text)
        assert found is None, f"{page.name}: {found.group(0)!r}"
