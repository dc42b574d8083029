"""The README's Python example runs, and prints what the README shows after it."""

import contextlib
import io
import re

from conftest import ROOT


def readme_blocks():
    """The README's `python` blocks, in order."""
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    return text, re.findall(r"```python\n(.*?)```", text, re.S)


def readme_example():
    """The README's first `python` block and the `text` block that follows it (its output)."""
    text, blocks = readme_blocks()
    assert blocks, "README.md has no python block"
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


def test_the_readme_further_python_examples_call_the_package_as_it_is():
    """The README's further examples (a search over parts, which runs for minutes) are five
    lines that compile, and each `cd.NAME(...)` they call is a function of the package whose
    signature takes the keywords given."""
    import inspect

    import codesign as cd

    _, blocks = readme_blocks()
    assert len(blocks) >= 2, "README.md shows no search over parts in Python"
    for code in blocks[1:]:
        assert len(code.strip().splitlines()) <= 5, code
        compile(code, "README.md", "exec")
        for name, arguments in re.findall(r"cd\.(\w+)\((.*?)\)\n", code):
            function = getattr(cd, name)
            keywords = re.findall(r"(\w+)=", arguments)
            parameters = inspect.signature(function).parameters
            assert all(k in parameters for k in keywords), (name, keywords)
