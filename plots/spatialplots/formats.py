"""The file formats every figure is written in, chosen once per run by the command line.

Families name their figures by a .png path and call figures.save_atomically; the format is a
run-wide choice (PNG for the plots/ folder, vector PDF for the paper's print figures), not a
family's, so it lives here instead of being passed through every family."""

SUPPORTED = ("png", "pdf")
_chosen = ["png"]


def choose(formats):
    unknown = [f for f in formats if f not in SUPPORTED]
    if unknown or not formats:
        raise ValueError(f"formats must be among {', '.join(SUPPORTED)}; got {formats}")
    _chosen[:] = list(dict.fromkeys(formats))


def chosen():
    return tuple(_chosen)


def paths(png_path):
    """The files one figure is written to: png_path with each chosen format's extension."""
    stem = png_path[:-4] if png_path.endswith(".png") else png_path
    return [f"{stem}.{fmt}" for fmt in _chosen]
