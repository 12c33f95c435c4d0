"""The regime classes of the sweep figures get colours a reader tells apart (issue 32: P1
and P3 were near-identical greens in the response and interval plots).

The measure is CIEDE2000 (Sharma, Wu & Dalal 2005), the CIE's colour difference, on the
colours as drawn (bands with transparency composited over the white background).  A
difference of about 2.3 is just noticeable; categories read as different colours rather
than shades of one from about 10 (Szafir 2017, "Modeling color difference for
visualization design", for marks of the size of a band), the threshold used here.
"""
import itertools

import numpy as np
import pytest
import xarray as xr
from matplotlib.colors import to_rgba

from vibimpact.plotting import plot_intervals, plot_response
from vibimpact.plotting import style

#: the smallest CIEDE2000 difference two classes must have
THRESHOLD = 10.0


def srgb_to_lab(rgb):
    """CIELAB (D65) of an sRGB colour with components in 0..1."""
    c = np.asarray(rgb, float)
    lin = np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)
    m = np.array([[0.4124564, 0.3575761, 0.1804375], [0.2126729, 0.7151522, 0.0721750],
                  [0.0193339, 0.1191920, 0.9503041]])
    xyz = m @ lin / np.array([0.95047, 1.0, 1.08883])
    f = np.where(xyz > (6 / 29) ** 3, np.cbrt(xyz), xyz / (3 * (6 / 29) ** 2) + 4 / 29)
    return np.array([116 * f[1] - 16, 500 * (f[0] - f[1]), 200 * (f[1] - f[2])])


def ciede2000(lab1, lab2):
    """The CIEDE2000 colour difference of two CIELAB colours (Sharma, Wu & Dalal 2005)."""
    (l1, a1, b1), (l2, a2, b2) = lab1, lab2
    cbar = (np.hypot(a1, b1) + np.hypot(a2, b2)) / 2
    g = 0.5 * (1 - np.sqrt(cbar ** 7 / (cbar ** 7 + 25.0 ** 7)))
    a1p, a2p = (1 + g) * a1, (1 + g) * a2
    c1p, c2p = np.hypot(a1p, b1), np.hypot(a2p, b2)
    h1p = np.degrees(np.arctan2(b1, a1p)) % 360 if c1p else 0.0
    h2p = np.degrees(np.arctan2(b2, a2p)) % 360 if c2p else 0.0
    dh = 0.0 if c1p * c2p == 0 else (h2p - h1p + 180) % 360 - 180
    dlp, dcp = l2 - l1, c2p - c1p
    dhp = 2 * np.sqrt(c1p * c2p) * np.sin(np.radians(dh) / 2)
    lbp, cbp = (l1 + l2) / 2, (c1p + c2p) / 2
    if c1p * c2p == 0:
        hbp = h1p + h2p
    elif abs(h1p - h2p) <= 180:
        hbp = (h1p + h2p) / 2
    else:
        hbp = (h1p + h2p + (360 if h1p + h2p < 360 else -360)) / 2
    t = (1 - 0.17 * np.cos(np.radians(hbp - 30)) + 0.24 * np.cos(np.radians(2 * hbp))
         + 0.32 * np.cos(np.radians(3 * hbp + 6)) - 0.20 * np.cos(np.radians(4 * hbp - 63)))
    dtheta = 30 * np.exp(-((hbp - 275) / 25) ** 2)
    rc = 2 * np.sqrt(cbp ** 7 / (cbp ** 7 + 25.0 ** 7))
    sl = 1 + 0.015 * (lbp - 50) ** 2 / np.sqrt(20 + (lbp - 50) ** 2)
    sc, sh = 1 + 0.045 * cbp, 1 + 0.015 * cbp * t
    rt = -np.sin(np.radians(2 * dtheta)) * rc
    return float(np.sqrt((dlp / sl) ** 2 + (dcp / sc) ** 2 + (dhp / sh) ** 2
                         + rt * (dcp / sc) * (dhp / sh)))


def drawn(rgba):
    """An RGBA colour composited over white: the colour a reader sees."""
    r, g, b, a = to_rgba(rgba)
    return tuple(round(a * c + (1 - a), 6) for c in (r, g, b))


def smallest_difference(colours):
    """``(difference, colour, colour)`` of the closest pair of ``colours`` (sRGB)."""
    labs = {c: srgb_to_lab(c) for c in colours}
    return min((ciede2000(labs[x], labs[y]), x, y)
               for x, y in itertools.combinations(labs, 2))


#: (regime, period) of every class the figures colour: not computed, each regime, P1..P8,
#: an unresolved period and one longer than the palette
CLASSES = ([(r, 0) for r in (0, 2, 3, 4, 5)]
           + [(1, n) for n in range(1, len(style.PERIOD_COLORS) + 1)] + [(1, 0), (1, 12)])


def every_class_sweep():
    """A one-direction sweep with one eta point per class of CLASSES (all impacting, so
    no hatching)."""
    regime = np.array([r for r, _ in CLASSES], "i1")
    period = np.array([n for _, n in CLASSES], "i4")
    label = np.array([f"class {r} {n}, 2 impacts" for r, n in CLASSES], dtype=object)
    k = len(CLASSES)
    eta = 1.0 + 0.01 * np.arange(k)
    data = {"regime": regime, "period": period, "label": label,
            "impacts_per_period": np.full(k, 2.0), "arcs": np.full(k, "1 arc", object),
            "X_m": np.linspace(0.5, 1.0, k), "Y_m": np.linspace(0.5, 1.0, k)}
    return xr.Dataset({n: ("eta", v) for n, v in data.items()}, coords={"eta": eta},
                      attrs={"sweep_direction": "up", "model": "rotor", "preset": "fig8"})


@pytest.mark.parametrize("lab1, lab2, expected", [
    ((50, 2.6772, -79.7751), (50, 0, -82.7485), 2.0425),
    ((50, -1.3802, -84.2814), (50, 0, -82.7485), 1.0),
    ((50, 0, 0), (50, -1, 2), 2.3669),
    ((50, 2.49, -0.001), (50, -2.49, 0.0009), 7.1792),
    ((50, 2.5, 0), (73, 25, -18), 27.1492),
    ((60.2574, -34.0099, 36.2677), (60.4626, -34.1751, 39.4387), 1.2644),
])
def test_ciede2000_matches_the_published_test_pairs(lab1, lab2, expected):
    """Hypothesis: the colour difference used below is CIEDE2000: it reproduces the test
    data of Sharma, Wu & Dalal (2005) to 1e-4 (hue wrap-around, the blue region's
    rotation term and neutral colours included)."""
    assert ciede2000(lab1, lab2) == pytest.approx(expected, abs=1e-4)
    assert srgb_to_lab((1.0, 1.0, 1.0)) == pytest.approx([100, 0, 0], abs=1e-3)


@pytest.mark.parametrize("alpha", [1.0, style.BAND_ALPHA])
def test_palette_classes_differ_by_at_least_the_category_threshold(alpha):
    """Hypothesis: every two classes of style.class_color (each regime, P1..P8, a long
    period) differ by CIEDE2000 >= 10, opaque (interval map) and at the response bands'
    transparency over white; the old palette fails this (P2/P6 2.7, P1/P3 7.7)."""
    colours = {drawn(to_rgba(style.class_color(r, n)[0], alpha)) for r, n in CLASSES}
    assert len(colours) == len(CLASSES) - 1  # an unresolved and a long period: one class
    assert smallest_difference(colours)[0] >= THRESHOLD
    old = ("#a1d99b", "#31a354", "#74c476", "#006d2c", "#c7e9c0", "#41ab5d")
    assert smallest_difference({drawn(to_rgba(c, alpha)) for c in old})[0] < THRESHOLD


def _band_colours_intervals(fig):
    ax = fig.axes[0]
    return {drawn(tuple(c)) for coll in ax.collections for c in coll.get_facecolor()}


def _band_colours_response(fig):
    return {drawn(p.get_facecolor()) for p in fig.axes[0].patches}


@pytest.mark.parametrize("plot, colours", [(plot_intervals, _band_colours_intervals),
                                           (plot_response, _band_colours_response)])
def test_drawn_bands_of_every_class_are_distinguishable(plot, colours):
    """Hypothesis: in the interval map and behind the response curves, the bands drawn
    for a sweep holding every class have one colour per class (the two long-period
    classes share one), and every two of them differ by CIEDE2000 >= 10 as drawn."""
    got = colours(plot(every_class_sweep()))
    assert len(got) == len(CLASSES) - 1
    diff, a, b = smallest_difference(got)
    assert diff >= THRESHOLD, (a, b)


def test_band_labels_are_readable_on_their_colour():
    """Hypothesis: the short label on a band is white on a dark colour and black on a
    light one (by relative luminance), not black on the dark blue of P2 or the wine of
    P7 as a rule keyed on the regime would make it."""
    assert style.text_color(style.class_color(1, 7)[0]) == "white"
    assert style.text_color(style.class_color(4, 0)[0]) == "white"
    assert style.text_color(style.class_color(1, 3)[0]) == "black"
    assert style.text_color(style.class_color(0, 0)[0]) == "black"
    fig = plot_intervals(every_class_sweep())
    short = {"QP": (2, 0), "C": (3, 0), "D": (4, 0), "U": (5, 0), "P": (1, 0)}
    texts = [t for t in fig.axes[0].texts if t.get_text()]  # not computed: no label
    assert len(texts) == len(CLASSES) - 1
    for text in texts:
        s = text.get_text()
        regime, period = short.get(s) or (1, int(s[1:]))
        assert text.get_color() == style.text_color(style.class_color(regime, period)[0]), s
