"""Reading the folders `yokai eval -o FOLDER` writes (imported from scripts/ by its siblings)."""
import json
import re
import sys


def read_json(path, program):
    """The JSON in `path`; else exit naming the file and what is wrong with it, as `program`."""
    try:
        return json.loads(path.read_text())
    except FileNotFoundError:
        sys.exit(f"{program}: {path}: no such file (is the folder a `yokai eval -o` output?)")
    except json.JSONDecodeError as e:
        sys.exit(f"{program}: {path}: not JSON ({e})")


def seed_numbers(labels):
    """The N of each label's `seed-N` (the last one in it), or None when a label has none."""
    numbers = [re.findall(r"seed-(\d+)", label) for label in labels]
    return [int(n[-1]) for n in numbers] if all(numbers) else None


def read_group(folder, group_index, program):
    """Group `group_index` of an evaluation folder: its `sp` and `xp` summaries (`xp` None
    for a group of one seed), SP R per seed (the matrix's diagonal, in the summary's seed
    order) and the seeds' numbers (`seed_numbers`). Exits naming the file when the folder
    lacks the group or a seed's self-play, as `program`."""
    groups = read_json(folder / "summary.json", program).get("groups", [])
    if group_index >= len(groups):
        sys.exit(f"{program}: {folder / 'summary.json'}: no group {group_index} (it has {len(groups)})")
    group = groups[group_index]
    diagonal = {
        e["row"]: e["metrics"]["reward"]
        for e in read_json(folder / "matrix.json", program)
        if e["row"] == e["col"]
    }
    missing = [s for s in group["seeds"] if s not in diagonal]
    if missing:
        sys.exit(f"{program}: {folder / 'matrix.json'}: no self-play entry for {missing[0]!r}")
    return {
        "sp": group["sp"],
        "xp": group.get("xp"),
        "per_seed": [diagonal[s] for s in group["seeds"]],
        "seed_numbers": seed_numbers(group["seeds"]),
    }
