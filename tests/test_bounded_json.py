"""JSON a file brings in is bounded in depth and size (issue 44, class 3).

Python's json module recurses: text nested 200,000 levels deep was a RecursionError
traceback from a checkpoint's request.json and from a sweep's or branch's ``params`` /
``settings`` attribute.  Every such read goes through :mod:`vibimpact.base._json`: one
ValueError naming the file or attribute, one line and exit 2 on the command line.
"""
import os
import re
import shutil
import threading

import netCDF4
import pytest

from vibimpact.base import _json
from vibimpact.base._regular import NotRegular
from vibimpact.engine.store import Checkpoint, read_record
from test_bad_input import assert_refused, listing, run_cli

DEEP_LISTS = "[" * 200_000 + "]" * 200_000
DEEP_OBJECTS = '{"a":' * 200_000 + "1" + "}" * 200_000


@pytest.mark.parametrize("text", [DEEP_LISTS, DEEP_OBJECTS], ids=["lists", "objects"])
def test_deep_json_is_one_value_error_naming_what_held_it(text):
    """Hypothesis: JSON nested 200,000 levels (lists or objects) is a ValueError that
    names its holder and the depth, never a RecursionError."""
    with pytest.raises(ValueError, match=r"^'s.nc' attribute 'x' is JSON nested more "
                                         r"than 100 levels deep$"):
        _json.loads(text, "'s.nc' attribute 'x'")


def test_brackets_inside_strings_and_shallow_json_pass():
    """Hypothesis: brackets inside strings (escaped quotes included) do not count as
    nesting, and JSON at the depth limit parses as json.loads would."""
    text = '{"a": "[[[[\\"[[[[{{{{", "b": ' + "[" * 99 + "1" + "]" * 99 + "}"
    value = _json.loads(text, "t")
    assert value["a"] == '[[[["[[[[{{{{'
    with pytest.raises(ValueError, match="nested more than 100"):
        _json.loads("[" * 101 + "]" * 101, "t")


@pytest.mark.parametrize("text, needle", [
    ("x" * 101, "larger than 100 bytes"),
    (b"\xff\xfe", "not UTF-8"),
    ("{", "t is not JSON"),
    (5, "not text (JSON), but int"),
])
def test_oversized_or_broken_json_is_refused_naming_it(text, needle):
    """Hypothesis: text over the size limit, bytes that are not UTF-8, broken JSON and
    a value that is not text are each one ValueError naming the holder."""
    with pytest.raises(ValueError, match=re.escape(needle)):
        _json.loads(text, "t", max_bytes=100)


def test_a_fifo_is_refused_without_waiting_for_a_writer(tmp_path):
    """Hypothesis: load_file of a FIFO returns at once with NotRegular (a plain open
    would wait for a writer forever)."""
    fifo = tmp_path / "f.json"
    os.mkfifo(fifo)
    got = []
    worker = threading.Thread(target=lambda: got.append(_catch(_json.load_file, fifo)),
                              daemon=True)
    worker.start()
    worker.join(10)
    assert not worker.is_alive(), "load_file blocked on a FIFO"
    assert isinstance(got[0], NotRegular) and "is a FIFO, not a regular file" in str(got[0])


def _catch(func, *args):
    try:
        return func(*args)
    except Exception as exc:  # noqa: BLE001 -- returned to the test
        return exc


def _checkpoint(tmp_path, text):
    ck = Checkpoint(tmp_path / "c.nc.partial").open("sweep", {"a": 1}, {"points": 2},
                                                    False)
    (ck.path / "request.json").write_text(text)
    return ck


@pytest.mark.parametrize("text", [DEEP_LISTS, DEEP_OBJECTS], ids=["lists", "objects"])
def test_a_deep_request_json_is_refused_by_resume_and_by_a_look(tmp_path, text):
    """Hypothesis: a checkpoint whose request.json nests 200,000 levels is refused by a
    resume (naming request.json and the depth) and by read_record (a map's partial
    view), each with a ValueError."""
    _checkpoint(tmp_path, text)
    with pytest.raises(ValueError, match="has no readable request.json .*nested more"):
        Checkpoint(tmp_path / "c.nc.partial").open("sweep", {"a": 1}, {"points": 2}, True)
    with pytest.raises(ValueError, match="not a vibimpact checkpoint: its request.json is "
                                         "JSON nested"):
        read_record(tmp_path / "c.nc.partial")


def test_a_deep_last_resume_or_output_stamp_reads_as_none(tmp_path):
    """Hypothesis: a deep last_resume.json reads as no last resume (zeros) and a deep
    output.json as no stamp, without a RecursionError."""
    from vibimpact.engine.leftovers import output_of

    ck = _checkpoint(tmp_path, '{"x": 1}')
    (ck.path / "last_resume.json").write_text(DEEP_LISTS)
    (ck.path / "output.json").write_text(DEEP_OBJECTS)
    (tmp_path / "c.nc").write_text("x")
    assert ck.last_resume()["points"] == 0
    assert output_of(ck, str(tmp_path / "c.nc")) is False


def test_resume_of_a_checkpoint_with_a_deep_request_is_one_line(tmp_path, monkeypatch,
                                                                capfd):
    """Hypothesis: classify --resume onto a checkpoint whose request.json is nested
    200,000 levels deep ends in one line naming request.json, exit 2, no output."""
    monkeypatch.chdir(tmp_path)
    _checkpoint(tmp_path, DEEP_LISTS)
    rc, out, err = run_cli(["classify", "--eta", "1.0", "--workers", "1", "--no-progress",
                            "-o", "c.nc", "--resume"], capfd)
    assert_refused(rc, out, err, "request.json is JSON nested more than 100 levels")
    assert listing(tmp_path) == ["c.nc.partial"]


@pytest.fixture(scope="module")
def sweep_file(tmp_path_factory):
    """A one-point classify file (written once for the module)."""
    d = tmp_path_factory.mktemp("sweep")
    old = os.getcwd()
    os.chdir(d)
    try:
        assert run_cli(["classify", "--eta", "1.0", "--workers", "1", "--no-progress",
                        "-o", "s.nc"], _NoCapture())[0] == 0
    finally:
        os.chdir(old)
    return d / "s.nc"


class _NoCapture:
    def readouterr(self):
        return "", ""


@pytest.mark.parametrize("argv", [
    ["plot", "s.nc", "-o", "p.png"],
    ["simulate", "--from", "s.nc", "--eta", "1.0", "-o", "o.nc"],
], ids=["plot", "simulate --from"])
def test_a_file_with_a_deep_params_attribute_is_one_line(argv, sweep_file, tmp_path,
                                                         monkeypatch, capfd):
    """Hypothesis: plot and simulate --from of a file whose 'params' attribute nests
    200,000 levels end in one line, exit 2, no file written, no traceback."""
    monkeypatch.chdir(tmp_path)
    shutil.copy(sweep_file, tmp_path / "s.nc")
    with netCDF4.Dataset(tmp_path / "s.nc", "a") as d:
        d.setncattr("params", DEEP_LISTS)
    rc, out, err = run_cli(argv, capfd)
    assert_refused(rc, out, err, "'params' attribute is JSON nested more than 100")
    assert listing(tmp_path) == ["s.nc"]


def test_a_map_store_with_a_deep_zarr_json_is_damaged(tmp_path):
    """Hypothesis: open_map of a store whose zarr.json nests 200,000 levels says the map
    is damaged, naming the depth (ValueError, no RecursionError)."""
    from vibimpact.maps.store import open_map

    store = tmp_path / "m.zarr"
    store.mkdir()
    (store / "zarr.json").write_text(DEEP_OBJECTS)
    with pytest.raises(ValueError, match="is damaged: .*nested more than 100"):
        open_map(store)
