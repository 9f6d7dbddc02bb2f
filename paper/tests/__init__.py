"""Tests of the paper: the lint over the hand-written .tex and the read-back of every generated
value.  Run from the repository root: /usr/bin/python3 -m unittest discover -s paper/tests -t paper"""
