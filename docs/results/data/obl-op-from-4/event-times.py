"""When a run reached an env step: the wall time (UTC) of the TensorBoard event nearest each
step asked for, and of the file's last event. `yokai train` writes one event file per start of
a run, so a run cut and resumed has two; this reads the first part's. Used for level 4's
times.txt (the first part ended at its checkpoint of update 2350, 2048 env steps per update):

    python3 docs/results/data/obl-op-from-4/event-times.py \
        runs/obl-op-from-4/level-4/seed-3/events.out.tfevents.1796575981.vm.14149.0 4812800
"""
import datetime
import struct
import sys


def events(path):
    """(step, wall_time) of each event: TFRecord frames holding Event protos, whose field 1
    is wall_time (double) and field 2 step (varint)."""
    data = open(path, "rb").read()
    i = 0
    while i + 12 <= len(data):
        (n,) = struct.unpack("<Q", data[i : i + 8])
        rec = data[i + 12 : i + 12 + n]
        i += 12 + n + 4
        if len(rec) > 10 and rec[0] == 0x09 and rec[9] == 0x10:
            (wall,) = struct.unpack("<d", rec[1:9])
            step, shift, j = 0, 0, 10
            while True:
                b = rec[j]
                step |= (b & 0x7F) << shift
                shift, j = shift + 7, j + 1
                if b < 0x80:
                    break
            yield step, wall


def utc(t):
    return datetime.datetime.fromtimestamp(t, datetime.timezone.utc).strftime("%H:%M:%S")


found = dict(events(sys.argv[1]))
for want in map(int, sys.argv[2:]):
    step = min(found, key=lambda s: abs(s - want))
    print(f"step {step}: {utc(found[step])}")
print(f"last event (step {max(found)}): {utc(max(found.values()))}")
