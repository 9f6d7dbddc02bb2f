"""Tests of plots/spatialplots: run from the repository root with
    /usr/bin/python3 -m unittest discover -s plots/tests -t plots
"""
