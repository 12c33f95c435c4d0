"""An image is written like a data file: through a temporary named after the writing
process (``.NAME.PID-*.tmp``), which the next write of the same image removes when that
process is gone (a SIGKILL during a figure's save left ``.b.png.XXXX.tmp`` for good)."""
import os
import subprocess

from matplotlib.figure import Figure

from vibimpact.io import check_output_path
from vibimpact.plotting import save_figure


def _dead_pid():
    proc = subprocess.Popen(["true"])
    proc.wait()
    return proc.pid


def test_a_figure_is_saved_through_a_temporary_of_its_own_process(tmp_path, monkeypatch):
    """Hypothesis: save_figure writes into ``.NAME.<its pid>-*.tmp`` beside the image and
    renames it: the temporary carries the pid a later run checks."""
    import tempfile

    seen = []
    real = tempfile.mkstemp

    def spy(*args, **kwargs):
        seen.append(kwargs.get("prefix"))
        return real(*args, **kwargs)

    monkeypatch.setattr(tempfile, "mkstemp", spy)
    fig = Figure(figsize=(2, 2))
    fig.subplots().plot([0, 1], [0, 1])
    save_figure(fig, tmp_path / "b.png")
    assert seen and set(seen) == {f".b.png.{os.getpid()}-"}
    assert [p.name for p in tmp_path.iterdir()] == ["b.png"]


def test_the_next_write_of_an_image_removes_a_dead_writers_temporary(tmp_path):
    """Hypothesis: checking an image's output path (what every command does first)
    removes the temporary a dead process left for that image, and leaves a live
    process's and another image's alone."""
    dead, live = _dead_pid(), os.getppid()
    stale = f".b.png.{dead}-x1.tmp"
    kept = [f".b.png.{live}-x1.tmp", f".c.png.{dead}-x1.tmp"]
    for n in [stale] + kept:
        (tmp_path / n).write_bytes(b"left")
    check_output_path(tmp_path / "b.png")
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(kept)
