"""Shorthands for the common quotes, so that a section says what it quotes and not how it is
formatted: a time in the table's unit, a ratio, a rate, a count, a problem size."""

from . import numbers


def _unit(groups, default="s"):
    for group in groups:
        for row in group:
            return row["unit"]
    return default


def time(book, key, rows, operation="value", looked_for=""):
    groups = [rows]
    return book.quote(key, operation, groups, lambda v: numbers.time(v, _unit(groups)),
                      looked_for)


def times(book, key, groups, operation, looked_for=""):
    """A min / max / geomean over several timed figures."""
    return book.quote(key, operation, groups, lambda v: numbers.time(v, _unit(groups)),
                      looked_for)


def ratio(book, key, groups, operation="value", looked_for=""):
    """A ratio row (groups=[rows]) or a ratio of two figures (operation='ratio')."""
    return book.quote(key, operation, groups, numbers.ratio, looked_for)


def plain(book, key, groups, operation="value", unit="", digits=3, looked_for=""):
    return book.quote(key, operation, groups, lambda v: numbers.plain(v, unit, digits),
                      looked_for)


def percent(book, key, groups, operation="value", looked_for=""):
    return book.quote(key, operation, groups, numbers.percent, looked_for)


def count(book, key, groups, operation="value", looked_for=""):
    return book.quote(key, operation, groups, numbers.count, looked_for)


def size(book, key, rows, looked_for=""):
    """The n the rows were measured at."""
    return book.quote(key, "n", [rows], numbers.size, looked_for)
