"""The README's Python example runs, and prints what the README shows after it."""

import contextlib
import io
import re

from conftest import ROOT


def readme_example():
    """The README's one `python` block and the `text` block that follows it (its output)."""
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    blocks = re.findall(r"```python\n(.*?)```", text, re.S)
    assert len(blocks) == 1, f"README.md has {len(blocks)} python blocks, expected one"
    after = text[text.index(blocks[0]) + len(blocks[0]):]
    shown = re.search(r"```text\n(.*?)```", after, re.S)
    assert shown, "README.md shows no output (a text block) after its python block"
    return blocks[0], shown.group(1)


def test_the_readme_python_example_prints_what_the_readme_shows(tmp_path, monkeypatch):
    code, shown = readme_example()
    assert len(code.strip().splitlines()) <= 5, "the README's example is meant to be five lines"
    # Run from elsewhere than the repository, as a user of the installed package would.
    monkeypatch.chdir(tmp_path)
    printed = io.StringIO()
    with contextlib.redirect_stdout(printed):
        exec(compile(code, "README.md", "exec"), {"__name__": "readme_example"})
    assert printed.getvalue() == shown
