"""The user docs' ``profilegen`` commands name subcommands, options, bundled sets and spec files
that exist (a renamed flag or file leaves a page that fails on the user's first try).

Fast: parses the pages and the CLI's argparse tree; runs no design.
"""

from __future__ import annotations

import argparse
import re
import shlex
from pathlib import Path

import pytest

from profilegen import cli

ROOT = Path(__file__).resolve().parents[1]
PAGES = [ROOT / "README.md", ROOT / "docs" / "getting-started.md", ROOT / "docs" / "index.md",
         *sorted((ROOT / "docs" / "guides").glob("*.md")), *sorted((ROOT / "docs" / "reference").glob("*.md"))]
FENCE = re.compile(r"^```[^\n]*\n(.*?)^```", re.S | re.M)
INLINE = re.compile(r"`(profilegen [^`]+)`")


def _commands(text: str) -> list[str]:
    """Every 'profilegen SUBCOMMAND ...' line of the page's code blocks and inline code."""
    found = []
    for block in FENCE.findall(text):
        for line in block.splitlines():
            line = line.split("#", 1)[0].strip()
            for part in line.split("&&"):
                part = part.strip()
                if part.startswith("profilegen "):
                    found.append(part)
    found += [m.strip() for m in INLINE.findall(text)]
    return found


def _subparsers() -> dict[str, argparse.ArgumentParser]:
    parser = cli._parser()
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            return dict(action.choices)
    raise AssertionError("profilegen's parser has no subcommands")


CASES = [(p.relative_to(ROOT).as_posix(), c) for p in PAGES for c in _commands(p.read_text(encoding="utf-8"))]


def test_the_pages_show_commands():
    # the parser of this test finds the quickstart's command (it cannot pass by finding nothing)
    assert ("README.md", "profilegen design") in CASES
    assert len(CASES) > 20


@pytest.mark.parametrize(("page", "command"), CASES, ids=[f"{p}:{c}" for p, c in CASES])
def test_doc_command_names_what_exists(page, command):
    subs = _subparsers()
    try:
        words = shlex.split(command)
    except ValueError:
        pytest.skip("not a whole command line")
    if len(words) < 2 or not re.fullmatch(r"[a-z]+", words[1]) or words[1] == "COMMAND":
        pytest.skip("a placeholder, not a command")
    sub = words[1]
    assert sub in subs, f"{page}: `{command}`: no subcommand {sub!r} (known: {sorted(subs)})"
    options = subs[sub]._option_string_actions
    for word in words[2:]:
        flag = word.split("=", 1)[0]
        if flag.startswith("-") and not re.search(r"[A-Z…]|\.\.\.|\\\|", flag):
            # '--torque-rated/-peak/-momentary' names three options
            base = flag.split("/")[0]
            assert base in options, f"{page}: `{command}`: {sub} has no option {flag!r}"
            for tail in flag.split("/")[1:]:
                stem = base.rsplit("-", 1)[0]
                assert f"{stem}{tail}" in options, f"{page}: `{command}`: {sub} has no option {stem + tail!r}"
    if sub in ("design", "app") and len(words) > 2 and not words[2].startswith("-"):
        name = words[2]
        if not name.endswith(".toml") and re.fullmatch(r"[a-z0-9_]+", name):
            assert (ROOT / "profiles" / f"{name}.toml").is_file(), f"{page}: `{command}`: no bundled set {name!r}"
    if sub in ("sweep", "optimize") and len(words) > 2 and words[2].startswith("profiles/"):
        assert (ROOT / words[2]).is_file(), f"{page}: `{command}`: no file {words[2]}"
