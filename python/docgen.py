"""Writes docs/python.md, the Python API reference, from coil's docstrings.

    python python/docgen.py            # rewrite docs/python.md
    python python/docgen.py --check    # exit 1 if docs/python.md is not up to date

python/tests/test_docs.py checks that the committed page is the generated one.
"""

import inspect
import pathlib
import sys

# The installed package (with its native module), not the sources beside this script.
HERE = pathlib.Path(__file__).resolve().parent
sys.path = [p for p in sys.path if pathlib.Path(p or ".").resolve() != HERE]
import coil  # noqa: E402

PAGE = pathlib.Path(__file__).resolve().parents[1] / "docs" / "python.md"

HEAD = """# coil from Python: API reference

Generated from the docstrings by `python python/docgen.py` (do not edit by hand). Every
example below runs in the tests (`python/tests/test_docs.py`), with `case` =
`cases/160ect`, `table4` = `cases/160ect/table4.json`, `tmp` a temporary folder and `repo`
the repository's root.

Install from the repository (cargo and Python >= 3.9; maturin builds the extension in
release):

```sh
pip install ./python                          # numpy and pandas come with it
pip install -r python/requirements.txt        # the versions tested, with dask[distributed]
```

Results are plain dicts, numpy arrays and pandas DataFrames with the names and units of
the binaries' JSON and CSV files; errors raise `coil.CoilError` with the binaries'
messages (file, line, what was expected). Running studies on Dask, on batch schedulers
and the tolerance study: [scale-out.md](scale-out.md).
"""


def render():
    parts = [HEAD, "\n## Module\n\n", inspect.cleandoc(coil.__doc__), "\n"]
    for name in coil.__all__:
        if name == "CoilError":
            continue
        function = getattr(coil, name)
        parts.append(f"\n## `coil.{name}{inspect.signature(function)}`\n\n")
        doc = inspect.cleandoc(function.__doc__)
        text, _, examples = doc.partition("\n>>>")
        parts.append(text.strip() + "\n")
        if examples:
            parts.append("\n```python\n>>>" + examples.rstrip() + "\n```\n")
    parts.append("\n## `coil.CoilError`\n\n" + inspect.cleandoc(coil.CoilError.__doc__) + "\n")
    return "".join(parts)


if __name__ == "__main__":
    text = render()
    if "--check" in sys.argv:
        sys.exit(0 if PAGE.read_text() == text else 1)
    PAGE.write_text(text)
