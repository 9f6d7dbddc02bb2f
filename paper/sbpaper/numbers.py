"""How a number is shown: three significant digits, a unit chosen so the mantissa stays
readable (ns / µs / ms / s), ratios with a times sign, counts grouped by thousands.

Every function returns (number_text, latex_text): number_text is the bare number as shown, which
the read-back test parses and compares with the CSV; latex_text adds the unit."""

import math

TIME_UNITS = (("ns", 1e-9), (r"\textmu s", 1e-6), ("ms", 1e-3), ("s", 1.0))
SECONDS = {"ns": 1e-9, "us": 1e-6, "\u00b5s": 1e-6, "ms": 1e-3, "s": 1.0}


def significant(value, digits=3):
    """value rounded to `digits` significant digits, as text without exponent."""
    if value == 0 or not math.isfinite(value):
        return "0" if value == 0 else "nan"
    decimals = max(0, digits - 1 - int(math.floor(math.log10(abs(value)))))
    text = f"{round(value, decimals):.{decimals}f}"
    return text


def grouped(integer):
    """65536 -> 65\\,536 (thin space between thousands)."""
    return f"{int(integer):,}".replace(",", r"\,")


def time(value, unit):
    """A duration in the table's unit -> the display unit that keeps the mantissa >= 1."""
    seconds = value * SECONDS[unit]
    name, scale = TIME_UNITS[0]
    for name, scale in TIME_UNITS:
        if seconds < scale * 1000 or name == "s":
            break
    text = significant(seconds / scale)
    return text, f"{text}\\,{name}", SECONDS[unit] / scale


def ratio(value):
    text = significant(value, 2 if value < 10 else 3)
    return text, f"{text}$\\times$", 1.0


def plain(value, unit="", digits=3):
    text = significant(value, digits)
    return text, (f"{text}\\,{unit}" if unit else text), 1.0


def percent(value):
    """A share in [0, 1] shown in percent."""
    text = significant(100.0 * value, 2)
    return text, f"{text}\\,\\%", 100.0


def count(value):
    text = grouped(round(value))
    return text, text, 1.0


def size(value):
    """A problem size n: 10^k when it is a power of ten, else grouped digits."""
    exponent = math.log10(value) if value > 0 else 0
    if value > 0 and abs(exponent - round(exponent)) < 1e-12 and value >= 1000:
        return f"10^{{{round(exponent)}}}", f"\\ensuremath{{10^{{{round(exponent)}}}}}", 1.0
    return count(value)
