"""The README's Python examples run as written and use only public names."""

import re

import pytest

from helpers.paths import REPO

BLOCKS = re.findall(r"```python\n(.*?)```", (REPO / "README.md").read_text(), flags=re.S)


def test_readme_has_python_examples():
    assert len(BLOCKS) >= 2


@pytest.mark.parametrize("index", range(len(BLOCKS)))
def test_readme_example_runs(index, capsys):
    code = BLOCKS[index]
    private = re.findall(r"diffsense[\w.]*\._\w+", code)
    assert not private, f"README example uses private names: {private}"
    exec(compile(code, f"README.md example {index}", "exec"), {})
