"""Reading the folders `yokai eval -o FOLDER` writes (imported from scripts/ by its siblings)."""
import json
import sys


def read_json(path, program):
    """The JSON in `path`; else exit naming the file and what is wrong with it, as `program`."""
    try:
        return json.loads(path.read_text())
    except FileNotFoundError:
        sys.exit(f"{program}: {path}: no such file (is the folder a `yokai eval -o` output?)")
    except json.JSONDecodeError as e:
        sys.exit(f"{program}: {path}: not JSON ({e})")
