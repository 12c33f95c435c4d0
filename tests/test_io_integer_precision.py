"""The writers never change an integer: CF-1.8 has no 64-bit integer type, so an int64
or unsigned variable is written as int32 when it fits, as float64 when float64 holds
each value exactly (magnitudes up to 2**53), and is refused otherwise."""
import os

import numpy as np
import pytest
import xarray as xr

import vibimpact as vi
from vibimpact.io import EXACT_FLOAT_INTEGER, for_file


def _write(writer, ds, path):
    """Write ``ds`` with ``writer`` ("netcdf" or "zarr") and read it back."""
    if writer == "netcdf":
        vi.io.write_netcdf(ds, path)
        return vi.io.read_netcdf(path)
    vi.maps.write_map(ds, path)
    return vi.maps.open_map(path)


BEYOND = {
    "2**53 + 1": [2**53 + 1, 0],
    "2**60 + 1": [2**53 + 1, 2**60 + 1],
    "-(2**53) - 1": [-(2**53) - 1, 7],
    "int64 max": [np.iinfo(np.int64).max, 0],
    "int64 min": [np.iinfo(np.int64).min, 0],
}


@pytest.mark.parametrize("writer,ext", [("netcdf", ".nc"), ("zarr", ".zarr")])
@pytest.mark.parametrize("case", list(BEYOND))
def test_an_integer_float64_cannot_hold_is_refused_naming_the_variable(case, writer, ext,
                                                                       tmp_path):
    """Hypothesis: an int64 variable beyond int32 was written as float64, so 2**53 + 1
    and 2**60 + 1 read back off by one; a magnitude beyond 2**53, of either sign, is now
    refused with a ValueError naming the variable, in a coordinate as in a data
    variable, and nothing is written."""
    values = np.array(BEYOND[case], dtype=np.int64)
    for ds in (xr.Dataset({"count": ("i", values)}),
               xr.Dataset(coords={"count": ("count", values)})):
        with pytest.raises(ValueError, match="variable 'count'.*2\\*\\*53"):
            _write(writer, ds, tmp_path / f"f{ext}")
        assert os.listdir(tmp_path) == []


def test_an_unsigned_integer_beyond_2_53_is_refused():
    """Hypothesis: uint64 values beyond 2**53 (which int64 cannot hold either) are
    refused alike by the conversion every writer uses."""
    ds = xr.Dataset({"n": ("i", np.array([2**64 - 1], dtype=np.uint64))})
    with pytest.raises(ValueError, match="variable 'n'"):
        for_file(ds, "test")


@pytest.mark.parametrize("writer,ext", [("netcdf", ".nc"), ("zarr", ".zarr")])
@pytest.mark.parametrize("values,stored", [
    ([2**31, -(2**31) - 1], "float64"),
    ([EXACT_FLOAT_INTEGER, -EXACT_FLOAT_INTEGER], "float64"),
    ([2**52 + 1, 3], "float64"),
    ([2**31 - 1, -(2**31)], "int32"),
])
def test_integers_float64_holds_exactly_are_written_and_read_back_unchanged(
        values, stored, writer, ext, tmp_path):
    """Hypothesis: the limit is float64's, not int32's: int64 values up to 2**53 in
    magnitude (both edges included) are written (as float64, or int32 where they fit)
    and read back as the same integers."""
    ds = xr.Dataset({"count": ("i", np.array(values, dtype=np.int64))})
    back = _write(writer, ds, tmp_path / f"f{ext}")
    assert back["count"].dtype == np.dtype(stored)
    assert [int(v) for v in back["count"].values] == values
