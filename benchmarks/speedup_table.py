"""The table that bench_executor.py and bench_collection.py print: wall time per
executor and worker count, the speed-up against the 1-worker row of the same kind,
the ratio to a reference row, and the largest difference from the reference result."""
from __future__ import annotations


def print_speedup_table(rows, ref, max_diff, *, base_wall: float, vs_label: str, diff_label: str) -> float:
    """``rows``: (name, kind, workers, start_s, wall_s, result); ``max_diff(result, ref)``.
    Prints the table; returns the largest difference."""
    one = {}
    for _, kind, w, _, wall, _ in rows:       # the first 1-worker row of each kind
        if w == 1:
            one.setdefault(kind, wall)
    width = max(len("executor"), *(len(r[0]) for r in rows))
    vw, dw = max(len(vs_label), 9), max(len(diff_label), 10)
    print()
    print(f"| {'executor':<{width}} | {'workers':>7} | {'start s':>7} | {'wall s':>7} | {'speed-up':>8} | "
          f"{vs_label:>{vw}} | {diff_label:>{dw}} |")
    print(f"|{'-' * (width + 2)}|{'-' * 9}|{'-' * 9}|{'-' * 9}|{'-' * 10}|{'-' * (vw + 2)}|{'-' * (dw + 2)}|")
    worst = 0.0
    for name, kind, w, start, wall, result in rows:
        d = max_diff(result, ref)
        worst = max(worst, d)
        speed = one.get(kind, wall) / wall if wall > 0 else float("inf")
        print(f"| {name:<{width}} | {w:>7} | {start:>7.2f} | {wall:>7.2f} | {speed:>7.2f}x | "
              f"{wall / base_wall:>{vw - 1}.2f}x | {d:>{dw}.3g} |")
    return worst
