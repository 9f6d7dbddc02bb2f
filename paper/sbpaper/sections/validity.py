"""Threats to validity, in numbers: how many rows the tables hold, how many carry no record of
what verified them (tables older than the check column), how many are unvalidated, and how
much a timed figure spreads over its repetitions."""

from .. import book as book_module

TIMED = {"time_per_op", "build_time", "fit_time", "time"}


def spread(ctx):
    """The median and the 90th percentile of (max - min) / value over the timed rows that
    record a spread (repetitions > 1)."""
    rows = [r for r in ctx.rows.usable if r["metric"] in TIMED and r.value > 0
            and r["repetitions"] not in ("", "0", "1") and r["max"] not in ("", "0")]
    spreads = sorted((float(r["max"]) - float(r["min"])) / r.value for r in rows)
    for q, key in ((0.5, "validity.spread.median"), (0.9, "validity.spread.p90")):
        if not spreads:
            ctx.book.missing(key, "timed rows with a spread")
            continue
        value = spreads[min(len(spreads) - 1, int(q * len(spreads)))]
        text = f"{100 * value:.0f}"
        ctx.book._add(key, {"text": text + r"\,\%", "operation": "spread_quantile",
                            "quantile": q, "files": sorted({r.file for r in rows}),
                            "value": value, "number": text, "scale": 100.0})


def generate(ctx):
    for criterion in book_module.TALLIES:
        book_module.tally(ctx.book, f"validity.{criterion.replace('_', '-')}", ctx.tables,
                          criterion)
    ctx.book.word("validity.tables", str(len(ctx.tables)))
    ctx.book.word("validity.tables-without-check",
                  str(sum(1 for t in ctx.tables if not t.has_check)))
    spread(ctx)
