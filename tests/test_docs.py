"""The documentation: the manual builds with ``mkdocs build --strict``, README.md stays a short user document,
every relative link in README.md and docs/ points at a file that exists, and every ``atcs`` command README.md
shows parses with the command line's own parser."""

import os
import re
import shlex
import subprocess
import sys
import unicodedata
from pathlib import Path

import pytest

from atcs.proofs.cli import build_parser
from atcs.proofs.cli._common import UsageError

ROOT = Path(__file__).resolve().parent.parent
README = ROOT / "README.md"
DOCS = ROOT / "docs"
README_MAX_LINES = 300
PAGES = sorted(DOCS.rglob("*.md"))

LINK = re.compile(r"!?\[[^\]]*\]\(([^)\s]+)(?:\s+\"[^\"]*\")?\)")
FENCE = re.compile(r"^\s*(```|~~~)")


def _without_code(text: str) -> str:
    """The text outside fenced code blocks and inline code spans, where links are links."""
    kept, fenced = [], False
    for line in text.splitlines():
        if FENCE.match(line):
            fenced = not fenced
            continue
        if not fenced:
            kept.append(re.sub(r"`[^`]*`", "", line))
    return "\n".join(kept)


def _fenced_lines(text: str) -> list[str]:
    """The lines inside fenced code blocks, a line ending in a backslash joined with the next."""
    lines, fenced, pending = [], False, ""
    for line in text.splitlines():
        if FENCE.match(line):
            fenced = not fenced
            continue
        if fenced:
            pending += line.rstrip()
            if pending.endswith("\\"):
                pending = pending[:-1] + " "
                continue
            lines.append(pending.strip())
            pending = ""
    return lines


def _relative_links(path: Path) -> list[str]:
    links = LINK.findall(_without_code(path.read_text(encoding="utf-8")))
    return [link for link in links if not re.match(r"^[a-z][a-z0-9+.-]*:", link) and not link.startswith("#")]


def _slug(heading: str) -> str:
    """A heading's anchor as MkDocs (Python-Markdown's toc) makes it."""
    text = re.sub(r"`([^`]*)`", r"\1", heading)
    text = unicodedata.normalize("NFKD", text).encode("ascii", "ignore").decode("ascii")
    text = re.sub(r"[^\w\s-]", "", text).strip().lower()
    return re.sub(r"[-\s]+", "-", text)


def _anchors(path: Path) -> set[str]:
    headings = re.findall(r"^#{1,6}\s+(.+?)\s*$", _without_fences(path.read_text(encoding="utf-8")), re.MULTILINE)
    return {_slug(h) for h in headings}


def _without_fences(text: str) -> str:
    kept, fenced = [], False
    for line in text.splitlines():
        if FENCE.match(line):
            fenced = not fenced
        elif not fenced:
            kept.append(line)
    return "\n".join(kept)


def test_the_manual_builds_strictly(tmp_path):
    """Strict: a broken link, a missing anchor or a page left out of the nav fails the build."""
    done = subprocess.run(
        [sys.executable, "-m", "mkdocs", "build", "--strict", "-f", str(ROOT / "mkdocs.yml"), "-d", str(tmp_path)],
        capture_output=True,
        text=True,
        check=False,
        cwd=ROOT,
        env={**os.environ, "NO_MKDOCS_2_WARNING": "1"},
        timeout=120,
    )
    assert done.returncode == 0, done.stdout + done.stderr
    assert (tmp_path / "index.html").exists()


def test_readme_is_short():
    lines = README.read_text(encoding="utf-8").splitlines()
    assert len(lines) <= README_MAX_LINES, f"README.md has {len(lines)} lines; the reference belongs in docs/"


@pytest.mark.parametrize("path", [README, *PAGES], ids=lambda p: str(p.relative_to(ROOT)))
def test_relative_links_point_at_files(path):
    missing = []
    for link in _relative_links(path):
        target, _, anchor = link.partition("#")
        file = (path.parent / target).resolve()
        if not file.is_file():
            missing.append(link)
        elif anchor and path == README and file.suffix == ".md" and anchor not in _anchors(file):
            missing.append(f"{link} (no such heading)")  # the manual's own anchors are checked by the strict build
    assert not missing, f"{path.relative_to(ROOT)}: {missing}"


def _readme_commands() -> list[str]:
    """Every ``atcs ...`` command in README.md's code blocks, also after ``&&``. README's examples are concrete
    (no placeholders), so every one must parse."""
    commands = []
    for line in _fenced_lines(README.read_text(encoding="utf-8")):
        for part in line.split("&&"):
            if part.strip().startswith("atcs "):
                commands.append(part.strip())
    return commands


def test_readme_shows_atcs_commands():
    assert len(_readme_commands()) >= 8


@pytest.mark.parametrize("command", _readme_commands())
def test_readme_command_parses(command):
    """The parser ``atcs`` itself uses (``build_parser``); parsing runs nothing."""
    argv = shlex.split(command)[1:]
    try:
        args = build_parser().parse_args(argv)
    except (SystemExit, UsageError) as exc:
        pytest.fail(f"{command!r} does not parse: {exc}")
    assert args.command == argv[0]


@pytest.mark.parametrize("path", [README, ROOT / "docs" / "property-scope.md"], ids=lambda p: p.name)
def test_the_property_count_is_current(path):
    """README and the property scope state how many properties are registered: the registry's count."""
    from atcs.properties import PROPERTIES

    stated = re.findall(r"(\d+) properties are registered", path.read_text(encoding="utf-8"))
    assert stated == [str(len(PROPERTIES))], f"{path.name} says {stated}; {len(PROPERTIES)} are registered"
