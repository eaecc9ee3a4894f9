"""Figures drawn in worker processes (diffsense.report.drawing): the same PNG bytes as drawn in
this process, written by this process into the output folder (its checks and manifest), a
figure that fails listed with the worker's reason, and a lost worker's figure drawn here."""

import json

import numpy as np
import pytest

from diffsense.report import figures
from diffsense.report.drawing import Drawer, DrawingError
from diffsense.report.files import MANIFEST, OutputError, OutputFolder

LABELS = ["aperture = 0.3 m", "power = 10 W", "range = 300 m", "noise figure = 6 dB"]
VALUES = np.array([1.9, 0.5, -3.8, -0.97])
KW = dict(title="Elasticities of snr_db", xlabel="Elasticity (dB per dB)")


def _drawn(tmp_path, workers):
    folder = OutputFolder(tmp_path / f"w{workers}")
    with Drawer(folder, workers) as drawer:
        path = drawer.draw(figures.tornado, "figures/tornado.png", LABELS, VALUES, **KW).result()
    return folder, path


def test_a_worker_draws_the_same_png_as_this_process(tmp_path):
    here_folder, here = _drawn(tmp_path, 0)
    there_folder, there = _drawn(tmp_path, 2)
    assert there == there_folder.path / "figures" / "tornado.png"
    png = there.read_bytes()
    assert png[:8] == b"\x89PNG\r\n\x1a\n" and len(png) > 10_000
    assert png == here.read_bytes()
    # written here, through the folder: listed in its manifest like a figure drawn in this process
    listed = json.loads((there_folder.path / MANIFEST).read_text())["files"]
    assert list(listed) == ["figures/tornado.png"]


def test_a_failing_figure_raises_the_workers_reason_and_the_others_are_drawn(tmp_path):
    folder = OutputFolder(tmp_path)
    with Drawer(folder, 2) as drawer:
        bad = drawer.draw(figures.tornado, "figures/bad.png", LABELS, np.zeros(4), **KW)
        good = drawer.draw(figures.tornado, "figures/good.png", LABELS, VALUES, **KW)
        with pytest.raises(DrawingError, match="ValueError: no input has a non-zero elasticity"):
            bad.result()
        assert good.result().exists()
    assert not (tmp_path / "figures" / "bad.png").exists()


def test_a_lost_worker_figure_is_drawn_here(tmp_path):
    folder = OutputFolder(tmp_path)
    drawer = Drawer(folder, 1)
    try:
        for w in drawer._workers:
            w.process.kill()
            w.process.wait()
        path = drawer.draw(figures.tornado, "figures/tornado.png", LABELS, VALUES, **KW).result()
        assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    finally:
        drawer.close()


def test_an_unsafe_or_foreign_file_is_refused_before_drawing(tmp_path):
    (tmp_path / "figures").mkdir()
    (tmp_path / "figures" / "mine.png").write_bytes(b"the user's own file")
    folder = OutputFolder(tmp_path)
    with Drawer(folder, 1) as drawer:
        with pytest.raises(OutputError, match="unsafe file name"):
            drawer.draw(figures.tornado, "../escape.png", LABELS, VALUES, **KW)
        with pytest.raises(OutputError, match="not written by diffsense"):
            drawer.draw(figures.tornado, "figures/mine.png", LABELS, VALUES, **KW)
    assert (tmp_path / "figures" / "mine.png").read_bytes() == b"the user's own file"
