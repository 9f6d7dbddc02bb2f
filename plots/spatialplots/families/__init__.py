"""Figure families: one module each, registered with @figure_family (spatialplots.family).

Every module in this package is imported by spatialplots.family.discover(); adding a family
means adding a module here (and its test under plots/tests/), nothing else.
"""
