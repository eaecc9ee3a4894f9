"""A figure-drawing worker process (:mod:`diffsense.report.drawing`): ``python -m
diffsense.report.draw_worker`` answers drawing requests on its standard input and output."""

import sys

from diffsense.report.drawing import _serve

if __name__ == "__main__":
    _serve(sys.stdin.buffer, sys.stdout.buffer)
