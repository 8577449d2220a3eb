"""Number formatting and markdown tables."""

import math


def fnum(x, digits=3):
    if x is None or (isinstance(x, float) and not math.isfinite(x)):
        return "—"
    if x == 0:
        return "0"
    mag = math.floor(math.log10(abs(x)))
    return f"{x:.{max(0, digits - 1 - mag)}f}"


def mrays(row):
    return fnum(row["items_per_second"] / 1e6) if row and "items_per_second" in row else err(row)


def err(row):
    if row is None:
        return "—"
    if "error" in row:
        return "error: " + row["error"]
    return "—"


def rate(row):
    return row.get("items_per_second") if row and "error" not in row else None


def ratio(a, b):
    return a / b if a is not None and b else None


def table(header, rows, left=1):
    """Markdown table; the first `left` columns are left-aligned, the rest (numbers) right-aligned."""
    out = ["| " + " | ".join(header) + " |", "|" + "|".join("---" if i < left else "---:" for i in range(len(header))) + "|"]
    out += ["| " + " | ".join(str(c) for c in r) + " |" for r in rows]
    return "\n".join(out) + "\n"
