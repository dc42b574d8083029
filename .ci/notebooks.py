"""Runs the example notebooks (examples/notebooks/NN_*.ipynb) in their reading order, each in a
fresh Python kernel with its own folder as the working directory, as a reader's Jupyter would.
The files are left as they are, without outputs. Prints each notebook's time on stderr; the
first cell that raises stops the run with its notebook, cell and traceback, exit 1.

    python3 -m pip install nbclient ipykernel matplotlib && python3 .ci/notebooks.py
"""

import pathlib
import sys
import time

import nbformat
from nbclient import NotebookClient
from nbclient.exceptions import CellExecutionError

FOLDER = pathlib.Path(__file__).resolve().parents[1] / "examples" / "notebooks"
TIMEOUT_S = 300  # per cell


def main() -> int:
    notebooks = sorted(FOLDER.glob("[0-9][0-9]_*.ipynb"))
    if not notebooks:
        print(f"notebooks: none found in {FOLDER}", file=sys.stderr)
        return 1
    for path in notebooks:
        start = time.monotonic()
        notebook = nbformat.read(path, as_version=4)
        client = NotebookClient(
            notebook,
            timeout=TIMEOUT_S,
            kernel_name="python3",
            resources={"metadata": {"path": str(path.parent)}},
        )
        try:
            client.execute()
        except CellExecutionError as error:
            print(f"notebooks: {path.name} failed:\n{error}", file=sys.stderr)
            return 1
        print(f"notebooks: {path.name}: {time.monotonic() - start:.1f} s", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
