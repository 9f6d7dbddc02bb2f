"""spatialplots: the figures of spatialbench, drawn from results/*.csv and results/registry.json.

Layout:
    io.py        reading and validating the CSV tables; reading the registry JSON
    registry.py  the registry (suites, structures, targets, complexities) as objects
    core.py      shared non-drawing helpers (params, names, units, statistics, validation rule)
    figures.py   shared drawing helpers (figure grids, legends, atomic writes, common panels)
    style.py     one colour/marker per structure, derived from the registry
    family.py    the @figure_family decorator and the discovery of family modules
    cli.py       the command line run by plots/plot_results.py
    families/    one module per figure family; each registers itself, none is listed by name
"""

import matplotlib

matplotlib.use("Agg")  # no display; runs before any module of the package imports pyplot
