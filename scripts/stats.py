"""Small statistics the results scripts share (imported from scripts/ by its siblings)."""
import math


def mean_se(xs):
    """Mean and standard error (sample SD / sqrt(n)) of `xs`; SE 0 for a single value."""
    n = len(xs)
    m = sum(xs) / n
    if n < 2:
        return m, 0.0
    return m, math.sqrt(sum((x - m) ** 2 for x in xs) / (n - 1) / n)
