"""Colour names people agree with: one object's pixels -> a basic colour term (and a second one).

The naming model is the XKCD colour survey (Munroe 2010: ~950 colours named by crowds of people,
shipped with matplotlib as `matplotlib._color_data.XKCD_COLORS`), chosen because it is a model
people made, it is already installed, and it covers the dark, washed-out and tinted colours of
real camera pixels that a hand-picked hue wheel names badly. Each survey name is given one of the
11 basic terms of `COLOUR_NAMES` by `basic_term` (its head word), and a pixel takes the basic term
of the survey colour nearest to it in CIELAB (CIE76 distance; cv2's sRGB -> Lab conversion).
Naming is a table look-up: every 8-level RGB cell (32^3 cells) is named once, on first use.

Before naming, the colour cast of the light is divided out (`frame_cast`; white-patch by
default, the best of the four methods measured on two rooms, on the pixels that can be white
under a correctable light, `white_candidates`; estimated on the object's surround with the
screens in view left out, `surround_cast`) and a reading drops what is not the object's own surface
colour (`surface_pixels`: specular highlights; for screens the light they emit).

White, grey and black are lightness, and lightness is relative: a pixel whose chroma lies under
the survey's own achromatic boundary (`achromatic_chroma`) is named by its luminance relative to
the white reference of the light on the object (`white_reference`), and an object's achromatic
pixels are named per surface (`shading_groups`): shading only darkens, so a surface is as light
as its lit part (a white cup in shade is white; a black cover under white print stays black).
`read_colour` names one view's pixels; `vote` combines views.
"""
from __future__ import annotations

import re
from dataclasses import dataclass
from functools import lru_cache
from typing import Any, Optional, Sequence, cast

import cv2
import numpy as np

from sg3d.core.model import COLOUR_NAMES

# Names whose words hold no basic term: the basic term people mean by the head word. Names
# that people split between two basic terms (teal, turquoise, aqua, khaki, beige, mauve, puce,
# rust, ...) are left out: their neighbours in the survey that do carry a basic word decide.
HEAD_WORD_TERMS = {
    "red": ("blood crimson scarlet ruby carmine cherry tomato vermillion rouge claret brick "
            "orangered lipstick strawberry cranberry raspberry burgundy maroon wine merlot "
            "bordeaux reddish"),
    "orange": "peach apricot tangerine pumpkin mango amber squash orangeish orangish",
    "yellow": ("gold golden mustard lemon canary dandelion sunflower butter banana maize saffron "
               "goldenrod custard cheese yellowish"),
    "green": ("lime olive sage mint spruce lichen fern wintergreen algae shamrock spearmint kiwi "
              "seaweed apple pistachio avocado evergreen jade emerald forest grass moss pine "
              "viridian celadon celery asparagus chartreuse camo leaf darkgreen lightgreen "
              "yellowgreen bluegreen swamp pea greenish"),
    "blue": ("navy azure azul cobalt cerulean sapphire ultramarine denim cornflower sky ocean "
             "marine midnight petrol royal darkblue lightblue greyblue greenblue blueberry bluish"),
    "purple": ("lavender lavendar lilac liliac violet plum eggplant aubergine amethyst grape "
               "orchid heliotrope wisteria iris indigo burple urple purply purpley purpleish "
               "purplish mulberry bruise barney heather blurple"),
    "pink": "rose rosa magenta fuchsia salmon coral blush bubblegum carnation watermelon pinky pinkish",
    "brown": ("tan sienna siena umber chocolate coffee mocha cocoa caramel chestnut mahogany "
              "auburn hazel camel sepia russet bronze taupe toupe mud dirt earth clay leather "
              "cinnamon poo poop shit brownish"),
    "white": "cream creme ivory eggshell",
    "grey": "gray silver charcoal slate steel gunmetal cement stone bluegrey greyish",
}
# Whole names the head-word rule gets wrong: the survey's "pale grey" is #fdfdfe, a white no
# person tells from #ffffff; left as grey it would claim every white pixel.
NAME_TERMS = {"pale grey": "white"}
_HEAD_TERM = {word: term for term, words in HEAD_WORD_TERMS.items() for word in words.split()}
_BASIC = set(COLOUR_NAMES) | {"gray"}

# A reading drops near-white clipped pixels (every channel at least this bright, the brightest
# one saturated) when they are at most SPECULAR_MAX_SHARE of it: a highlight, not a white object.
SPECULAR_MIN = 200
SPECULAR_CLIP = 245
SPECULAR_MAX_SHARE = 0.25
# A screen's own colour is its frame and its dark glass; what it shows is light it emits. Of a
# screen's pixels those brighter than this luma (0-255) are dropped, unless under
# SCREEN_MIN_KEPT of them would remain (then the screen itself is light-coloured).
SCREEN_MAX_LUMA = 90
SCREEN_MIN_KEPT = 0.1
# Labels whose objects are screens (what they show is not their colour).
SCREEN_LABELS = frozenset({"tv", "laptop", "cell phone", "monitor"})
# A view's weight for the vote: full from this many object pixels on (smaller views are noisy),
# half at a crop sharpness (variance of the Laplacian) of SHARP_HALF, and BORDER_WEIGHT when
# the image border cuts the box (the object is partly out of view).
FULL_VIEW_PIXELS = 2500
SHARP_HALF = 30.0
BORDER_WEIGHT = 0.3
# Cast gains are bounded: a frame dominated by one coloured wall is not all cast; nor is a
# frame without any dark surface black-pointed by more than MAX_BLACK.
MAX_GAIN = 1.4
MAX_BLACK = 40
# Fewer pixels than this are not enough to estimate a cast from.
MIN_CAST_PIXELS = 100
CAST_METHOD = "white-patch"
# The light falling on an object is estimated on its surround: its box widened by SURROUND
# times its own width and height on each side (clipped to the image), sampled to about
# CAST_SAMPLES pixels. Narrower, the object is its own white reference (a light wooden chair
# reads grey); much wider, it is the whole frame, whose light is not the object's (a white cup
# lit warm by the table it stands on reads brown). Kitchen colour agreement at 0.5, 1, 2 and 3
# widths: 10, 11, 11 and 10 of 12 matched objects; the living room's named objects alike at all.
SURROUND = 2.0
CAST_SAMPLES = 1200
# A second colour is kept when the views agree it covers at least this share of the object
# (a quarter: a clear part, not the noise at its edges) and it is not merely a shade of the
# first: light and shadow move a surface between neighbouring achromatic terms.
SECOND_MIN_SHARE = 0.25
# Mean shares are compared to this many decimals (`vote`).
SHARE_DECIMALS = 9
SHADES = {frozenset(("white", "grey")), frozenset(("grey", "black"))}
LUT_LEVELS = 32
# Camera pixels of surfaces are duller than the survey's colours, which people named on
# screens: before the nearest survey colour is found a pixel's chroma is raised CHROMA_GAIN
# times, to at most CHROMA_CAP unless it is already more vivid (`boost_chroma`; without it
# wooden chairs and tables read grey).
CHROMA_GAIN = 2.0
CHROMA_CAP = 40.0
# Survey colours were named as light from a screen (black L* 0, white 100); a camera sees
# surfaces, whose black reflects a few per cent of the light (Munsell N2, L* about 20) and whose
# white about 90 % (N9.5, L* about 96). A pixel's lightness is stretched from that range onto
# the screen's before naming: a black TV frame at L* 21 is black, not the survey's "dark grey".
SURFACE_BLACK_L = 20.0
SURFACE_WHITE_L = 96.0
# White, grey and black name lightness, not hue: a pixel whose chroma, as read for naming, lies
# below the survey's own boundary between its achromatic and chromatic colours
# (`achromatic_chroma`) is named by its lightness alone (`achromatic_term`), so a shaded white
# cup's faint blue tint or a cream cup's faint yellow is not boosted into "blue" or "brown".
ACHROMATIC = ("white", "grey", "black")
# Lightness is relative (`relative_luminance`): to the white reference of the light on the
# object (the WHITE_PERCENTILE of the luminance of the unclipped achromatic pixels of its
# surround, `white_reference`) and, for one object, to
# its own lit part (`shading_groups`): shading only darkens a surface, so the achromatic pixels
# within SHADING_RANGE (a luminance ratio) of the LIT_PERCENTILE of the object's achromatic
# luminance are one surface named by that lit level; darker ones are another surface (a black
# cover under white print) and are grouped the same way in turn.
WHITE_PERCENTILE = 99
LIT_PERCENTILE = 90
SHADING_RANGE = 4.0
MAX_SHADING_GROUPS = 3


def basic_term(xkcd_name: str) -> Optional[str]:
    """The basic colour term (COLOUR_NAMES) of one XKCD survey name, None to leave it out.

    Rule: English colour compounds put the head last ("blue green" is a green, "greenish blue"
    a blue, "reddish brown" a brown), so the name's last word that is a basic term names it
    ("gray" spelled either way); words after "with" only qualify ("blue with a hint of purple").
    A name with no basic word takes its last word's term from HEAD_WORD_TERMS (navy -> blue,
    maroon -> red, cream -> white); otherwise it is left out. NAME_TERMS overrides whole names."""
    name = xkcd_name.lower().removeprefix("xkcd:")
    if name in NAME_TERMS:
        return NAME_TERMS[name]
    name = name.split(" with ")[0]
    words = [w for w in re.split(r"[ /\-']+", name) if w]
    basic = [w for w in words if w in _BASIC]
    if basic:
        return "grey" if basic[-1] == "gray" else basic[-1]
    for w in reversed(words):
        if w in _HEAD_TERM:
            return _HEAD_TERM[w]
    return None


def survey_colours() -> tuple[np.ndarray, np.ndarray]:
    """(RGB uint8 N x 3, index into COLOUR_NAMES N) of every XKCD survey colour with a basic term."""
    from matplotlib._color_data import XKCD_COLORS

    rgb, term = [], []
    for name, hexcode in XKCD_COLORS.items():
        t = basic_term(name)
        if t is not None:
            h = cast(str, hexcode).lstrip("#")   # the stub says any ColorType; XKCD's are "#rrggbb"
            rgb.append([int(h[i:i + 2], 16) for i in (0, 2, 4)])
            term.append(COLOUR_NAMES.index(t))
    return np.array(rgb, np.uint8), np.array(term, np.int16)


def rgb_to_lab(rgb: np.ndarray) -> np.ndarray:
    """sRGB uint8 (..., 3) -> CIELAB float32 (L 0-100, a, b), cv2's D65 conversion."""
    flat = np.asarray(rgb, np.float32).reshape(-1, 1, 3) / 255.0
    return cv2.cvtColor(flat, cv2.COLOR_RGB2Lab).reshape(np.shape(rgb))


def bgr_to_lab(bgr: np.ndarray) -> np.ndarray:
    """BGR uint8 pixels (N x 3) -> CIELAB float32 (N x 3) through cv2's 8-bit conversion (L* to
    0.4, a* and b* to 1: finer than a camera's noise), passed as one image row (cv2 converts a
    row at a time)."""
    lab = cv2.cvtColor(np.ascontiguousarray(bgr, np.uint8).reshape(1, -1, 3), cv2.COLOR_BGR2Lab).reshape(-1, 3)
    out = lab.astype(np.float32)
    out[:, 0] *= 100.0 / 255.0
    out[:, 1:] -= 128.0
    return out


def boost_chroma(lab: np.ndarray, gain: float = CHROMA_GAIN, cap: float = CHROMA_CAP) -> np.ndarray:
    """CIELAB colours (N x 3) with chroma C raised to min(gain * C, max(C, cap)), hue and
    lightness kept: dull camera pixels move towards the chroma people's named colours have,
    already vivid ones stay as they are."""
    out = np.array(lab, np.float32, copy=True)
    c = np.hypot(out[:, 1], out[:, 2])
    target = np.minimum(gain * c, np.maximum(c, cap))
    scale = np.divide(target, c, out=np.ones_like(c), where=c > 1e-6)
    out[:, 1:] *= scale[:, None]
    return out


def surface_lightness(lab: np.ndarray, black: float = SURFACE_BLACK_L, white: float = SURFACE_WHITE_L) -> np.ndarray:
    """CIELAB colours (N x 3) with the lightness of surfaces (black ones at `black`, white ones
    at `white`) stretched onto the survey's 0-100 (a screen's black and white)."""
    out = np.array(lab, np.float32, copy=True)
    out[:, 0] = np.clip((out[:, 0] - black) * 100.0 / (white - black), 0.0, 100.0)
    return out


def build_lut(levels: int = LUT_LEVELS, chroma_gain: float = CHROMA_GAIN, chroma_cap: float = CHROMA_CAP,
              black: float = SURFACE_BLACK_L, white: float = SURFACE_WHITE_L) -> np.ndarray:
    """Basic term index for every RGB cell of a levels^3 grid (B-major: index = (b * levels + g)
    * levels + r, the order of BGR pixels), from the nearest survey colour in CIELAB to the cell's
    colour read as a surface (`surface_lightness` from `black` and `white`) with its chroma
    boosted (`boost_chroma`)."""
    from scipy.spatial import cKDTree

    rgb, term = survey_colours()
    step = 256 // levels
    centres = (np.arange(levels) * step + step // 2).astype(np.uint8)
    b, g, r = np.meshgrid(centres, centres, centres, indexing="ij")
    cells = np.stack([r.ravel(), g.ravel(), b.ravel()], axis=1)
    pixels = boost_chroma(surface_lightness(rgb_to_lab(cells), black, white), chroma_gain, chroma_cap)
    _, nearest = cKDTree(rgb_to_lab(rgb)).query(pixels)
    return term[nearest]


_SHIFT = int(np.log2(256 // LUT_LEVELS))


@lru_cache(maxsize=1)
def survey_lut() -> np.ndarray:
    """The default `build_lut`, built once, on first use (~40 ms)."""
    return build_lut()


def name_pixels(bgr: np.ndarray) -> np.ndarray:
    """COLOUR_NAMES index of every BGR uint8 pixel (N x 3 or H x W x 3), via the survey LUT."""
    q = (np.asarray(bgr, np.uint8).reshape(-1, 3) >> _SHIFT).astype(np.int32)
    return survey_lut()[(q[:, 0] * LUT_LEVELS + q[:, 1]) * LUT_LEVELS + q[:, 2]]


@lru_cache(maxsize=1)
def achromatic_chroma() -> float:
    """The chroma (CIELAB C*) that best splits the survey's white, grey and black colours from
    all its other colours: the threshold misnaming fewest survey colours as one or the other
    (about 16; the survey's own boundary, not a hand-picked one)."""
    rgb, term = survey_colours()
    lab = rgb_to_lab(rgb)
    chroma = np.hypot(lab[:, 1], lab[:, 2])
    grey = np.isin(term, [COLOUR_NAMES.index(c) for c in ACHROMATIC])
    candidates = np.unique(np.round(chroma, 1))
    errors = [int(((chroma < t) & ~grey).sum() + ((chroma >= t) & grey).sum()) for t in candidates]
    return float(candidates[int(np.argmin(errors))])


def is_achromatic(lab: np.ndarray) -> np.ndarray:
    """Whether each CIELAB colour (N x 3) is white, grey or black to the survey: its chroma as
    read for naming (`boost_chroma`) under `achromatic_chroma`."""
    c = np.hypot(lab[:, 1], lab[:, 2])
    return np.minimum(CHROMA_GAIN * c, np.maximum(c, CHROMA_CAP)) < achromatic_chroma()


def lab_luminance(lightness: Any) -> Any:
    """CIE relative luminance Y (0-1) of CIELAB lightness L* (0-100) (CIE 1976 inverse)."""
    f = (np.asarray(lightness, np.float32) + 16.0) / 116.0
    return np.where(f > 6 / 29, f * f * f, 3 * (6 / 29) ** 2 * (f - 4 / 29))


def luminance_lightness(y: Any) -> Any:
    """CIELAB lightness L* (0-100) of CIE relative luminance Y (0-1) (CIE 1976)."""
    y = np.asarray(y, np.float64)
    f = np.where(y > (6 / 29) ** 3, np.cbrt(y), y / (3 * (6 / 29) ** 2) + 4 / 29)
    return 116.0 * f - 16.0


@lru_cache(maxsize=1)
def _neutral_survey() -> tuple[np.ndarray, np.ndarray]:
    rgb, term = survey_colours()
    lab = rgb_to_lab(rgb)
    neutral = np.isin(term, [COLOUR_NAMES.index(c) for c in ACHROMATIC]) & \
        (np.hypot(lab[:, 1], lab[:, 2]) < achromatic_chroma())
    order = np.argsort(lab[neutral, 0])
    return lab[neutral, 0][order], term[neutral][order]


def achromatic_term(lightness: Any) -> np.ndarray:
    """COLOUR_NAMES index (white, grey or black) of surface lightness L* (array): the survey's
    neutral colour (achromatic term, chroma under `achromatic_chroma`) nearest in lightness once
    the surface's lightness is stretched onto the survey's (`surface_lightness`); a look-up in
    steps of 0.1 L*."""
    i = np.clip(np.rint(np.asarray(lightness, np.float64) * 10), 0, 1000).astype(np.int64)
    return _achromatic_table()[i]


@lru_cache(maxsize=1)
def _achromatic_table() -> np.ndarray:
    light, term = _neutral_survey()
    lab = np.zeros((1001, 3), np.float32)
    lab[:, 0] = np.linspace(0.0, 100.0, 1001)
    seen = surface_lightness(lab)[:, 0]
    i = np.clip(np.searchsorted(light, seen), 1, len(light) - 1)
    nearer_low = (seen - light[i - 1]) <= (light[i] - seen)
    return term[np.where(nearer_low, i - 1, i)].astype(np.int64)


def relative_luminance(lightness: Any, white: float) -> np.ndarray:
    """Luminance (CIE Y) of lightness L* relative to a white reference of luminance `white`
    (CIE Y, 0-1): the white reference reads 1, nothing reads past it."""
    return np.clip(lab_luminance(lightness) / max(float(white), 1e-3), 0.0, 1.0)


def relative_lightness(lightness: Any, white: float) -> np.ndarray:
    """Lightness L* relative to a white reference of luminance `white` (`relative_luminance`,
    as lightness: the white reference reads L* 100)."""
    return luminance_lightness(relative_luminance(lightness, white))


def _at_percentile(ascending: np.ndarray, percentile: float) -> Any:
    """The value at `percentile` of an ascending array (nearest rank)."""
    return ascending[round((len(ascending) - 1) * percentile / 100.0)]


def shading_groups(ascending: np.ndarray) -> list[tuple[int, int]]:
    """The achromatic pixels of one object (their relative luminance, ascending) split into
    surfaces, as [lo, hi) index ranges: shading only darkens, so the pixels within SHADING_RANGE
    of the object's lit part (the LIT_PERCENTILE of their luminance) are one surface; the darker
    rest is grouped the same way, at most MAX_SHADING_GROUPS times (the last takes what is left)."""
    groups: list[tuple[int, int]]
    groups, hi = [], len(ascending)
    while hi > 0:
        lit = _at_percentile(ascending[:hi], LIT_PERCENTILE)
        last = len(groups) == MAX_SHADING_GROUPS - 1
        lo = 0 if last else int(np.searchsorted(ascending[:hi], lit / SHADING_RANGE))
        groups.append((lo, hi))
        hi = lo
    return groups


def surface_term(ascending: np.ndarray) -> int:
    """COLOUR_NAMES index of one achromatic surface from its pixels' relative luminance
    (ascending): white when its lit part (LIT_PERCENTILE) is white, as shading darkens a white
    surface but nothing lights it past white; otherwise the term of its median pixel, as a gloss
    lights a dark surface's reflections while most of it keeps its own grey or black."""
    lit = int(achromatic_term(luminance_lightness(_at_percentile(ascending, LIT_PERCENTILE))))
    if COLOUR_NAMES[lit] == "white":
        return lit
    return int(achromatic_term(luminance_lightness(_at_percentile(ascending, 50))))


def name_achromatic(lightness: np.ndarray, white: float = 1.0) -> np.ndarray:
    """COLOUR_NAMES index of each achromatic pixel of one object (its L*), relative to the
    white reference of luminance `white` (`relative_luminance`): every pixel of one surface
    (`shading_groups`) takes that surface's term (`surface_term`)."""
    y = relative_luminance(lightness, white)
    order = np.argsort(y, kind="stable")
    ascending = y[order]
    names = np.empty(len(y), np.int64)
    for lo, hi in shading_groups(ascending):
        names[order[lo:hi]] = surface_term(ascending[lo:hi])
    return names


@dataclass(frozen=True)
class Cast:
    """A frame's colour cast: pixels are corrected as (pixel - black) * gains, per channel (B, G, R);
    `white` is the relative luminance (CIE Y, 0-1) of the frame's white reference once corrected."""

    gains: np.ndarray
    black: np.ndarray
    white: float = 1.0

    @classmethod
    def none(cls) -> "Cast":
        return cls(np.ones(3, np.float32), np.zeros(3, np.float32))


def frame_cast(image: np.ndarray, method: str = CAST_METHOD) -> Cast:
    """The colour cast of a frame (a sample of its pixels is enough), to divide out before naming.

    "grey-world" (Buchsbaum 1980): the scene's mean colour is grey, so each channel is scaled to
    the largest of the three channel means (never darkened: a white stays white). "white-patch" (Land's retinex, max-RGB): the brightest
    surfaces are white, so each channel is scaled until its 99th percentile meets the largest;
    the percentiles are taken over the pixels that can be white under a correctable cast
    (`white_candidates`), as max-RGB is otherwise led by any vivid bright colour.
    "levels": white-patch that also takes the darkest surfaces as black (each channel's 1st
    percentile becomes 0, its 99th 255), the camera's exposure undone as well as its tint.
    "none": no correction. Clipped and near-black pixels are left out of the estimates; gains
    are bounded to [1 / MAX_GAIN, MAX_GAIN] and the black point to MAX_BLACK. The frame's white
    reference (`white_reference`) is measured on the corrected pixels."""
    if method == "none":
        return Cast.none()
    px = np.asarray(image, np.uint8).reshape(-1, 3)
    lit = px[(channel_max(px) < SPECULAR_CLIP) & (channel_min(px) > 10)]
    if len(lit) < MIN_CAST_PIXELS:
        return Cast.none()
    black = np.zeros(3, np.float32)
    if method == "grey-world":
        means = lit.mean(axis=0)
        gains = means.max() / np.maximum(means, 1.0)
    elif method == "white-patch":
        top = np.percentile(white_candidates(lit), 99, axis=0)
        gains = top.max() / np.maximum(top, 1.0)
    elif method == "levels":
        black = np.minimum(np.percentile(px, 1, axis=0), MAX_BLACK).astype(np.float32)
        top = np.percentile(px, 99, axis=0)
        gains = 255.0 / np.maximum(top - black, 1.0)
    else:
        raise ValueError(f"unknown colour-cast method {method!r} (grey-world, white-patch, levels, none)")
    gains = np.clip(gains, 1 / MAX_GAIN, MAX_GAIN).astype(np.float32)
    return Cast(gains, black, white_reference(apply_cast(lit, Cast(gains, black))))


def white_candidates(px: np.ndarray, max_gain: float = MAX_GAIN) -> np.ndarray:
    """The pixels (N x 3) that can be a white surface under a light whose cast is correctable
    (every channel's gain within [1 / max_gain, max_gain]): brightest channel at most max_gain^2
    times the darkest. Others (the fire on a screen, a lamp's orange glow) are no light's white,
    and white-patch would take their own colour for the light's. All pixels when under
    MIN_CAST_PIXELS qualify (a view filled by one vivid surface: its light cannot be told)."""
    white = channel_max(px).astype(np.float32) <= max_gain * max_gain * channel_min(px)
    return px[white] if white.sum() >= MIN_CAST_PIXELS else px


def channel_min(px: np.ndarray) -> np.ndarray:
    """Each pixel's darkest channel (N x 3 -> N), channel by channel: numpy's reduce over a
    3-wide axis costs several times more."""
    return np.minimum(np.minimum(px[:, 0], px[:, 1]), px[:, 2])


def channel_max(px: np.ndarray) -> np.ndarray:
    """Each pixel's brightest channel (N x 3 -> N), as `channel_min`."""
    return np.maximum(np.maximum(px[:, 0], px[:, 1]), px[:, 2])


def surround_bounds(bounds: tuple[int, int, int, int], width: int, height: int,
                    widths: float = SURROUND) -> tuple[int, int, int, int]:
    """The surround of a box (x1, y1, x2, y2; x2/y2 exclusive): the box widened by `widths` times
    its own width and height on each side, clipped to a width x height image."""
    x1, y1, x2, y2 = bounds
    dx, dy = widths * (x2 - x1), widths * (y2 - y1)
    return (max(0, int(x1 - dx)), max(0, int(y1 - dy)), min(width, int(np.ceil(x2 + dx))),
            min(height, int(np.ceil(y2 + dy))))


def surround_cast(image: np.ndarray, bounds: tuple[int, int, int, int], method: str = CAST_METHOD,
                  emitters: Sequence[tuple[int, int, int, int]] = ()) -> Cast:
    """The colour cast and white reference of the light falling on the object in a box of a BGR
    image: `frame_cast` on the local framework of lightness perception (the object with its
    surround, `surround_bounds`), sampled to about CAST_SAMPLES pixels. The boxes of `emitters`
    in view (screens: what they show is light they emit, not light falling on their
    neighbours, and a bright picture would set the white of a shaded room) are left out of the
    surround, except where they overlap the object's own box."""
    x1, y1, x2, y2 = surround_bounds(bounds, image.shape[1], image.shape[0])
    step = max(1, int(np.ceil(np.sqrt((x2 - x1) * (y2 - y1) / CAST_SAMPLES))))
    sample = image[y1:y2:step, x1:x2:step]
    if not emitters:
        return frame_cast(sample, method)
    ys, xs = np.arange(y1, y2, step)[:, None], np.arange(x1, x2, step)[None, :]
    keep = np.ones(sample.shape[:2], bool)
    for ex1, ey1, ex2, ey2 in emitters:
        keep &= ~((ys >= ey1) & (ys < ey2) & (xs >= ex1) & (xs < ex2))
    bx1, by1, bx2, by2 = bounds
    keep |= (ys >= by1) & (ys < by2) & (xs >= bx1) & (xs < bx2)
    return frame_cast(sample[keep], method)


def white_reference(bgr: np.ndarray, percentile: float = WHITE_PERCENTILE) -> float:
    """The luminance (CIE Y, 0-1) a frame's white surfaces have: the `percentile` of the luminance
    of its achromatic pixels (chroma under `achromatic_chroma` as read for naming), 1.0 when it
    has none. Retinex's white patch, on lightness instead of on each channel."""
    lab = bgr_to_lab(bgr)
    grey = is_achromatic(lab)
    if not grey.any():
        return 1.0
    return float(lab_luminance(np.percentile(lab[grey, 0], percentile)))


def apply_cast(bgr: np.ndarray, cast: Optional[Cast]) -> np.ndarray:
    """BGR uint8 pixels (N x 3) with a cast divided out (clipped to 0-255)."""
    px = np.asarray(bgr, np.uint8).reshape(-1, 3)
    if cast is None:
        return px
    return np.clip((px.astype(np.float32) - cast.black) * cast.gains, 0, 255).astype(np.uint8)


def surface_pixels(bgr: np.ndarray, screen: bool = False) -> np.ndarray:
    """The pixels that show the surface's own colour (N x 3 BGR): specular highlights (near-white,
    clipped, at most SPECULAR_MAX_SHARE of the pixels) dropped; for a screen, the light it emits
    (luma above SCREEN_MAX_LUMA) dropped unless that leaves under SCREEN_MIN_KEPT of them."""
    px = np.asarray(bgr, np.uint8).reshape(-1, 3)
    if len(px) == 0:
        return px
    highlight = (channel_min(px) >= SPECULAR_MIN) & (channel_max(px) >= SPECULAR_CLIP)
    if 0 < highlight.mean() <= SPECULAR_MAX_SHARE:
        px = px[~highlight]
    if screen and len(px):
        luma = px.astype(np.float32) @ np.array([0.114, 0.587, 0.299], np.float32)
        dark = luma <= SCREEN_MAX_LUMA
        if dark.mean() >= SCREEN_MIN_KEPT:
            px = px[dark]
    return px


def is_screen(label: Optional[str]) -> bool:
    """Whether objects of this label are screens (SCREEN_LABELS)."""
    return label is not None and label.strip().lower() in SCREEN_LABELS


def view_weight(pixels: float, sharpness: float, cut: bool) -> float:
    """How well one view shows an object's colour, in [0, 1]: min(1, pixels / FULL_VIEW_PIXELS)
    (area of the object's pixels) x sharpness / (sharpness + SHARP_HALF) (motion blur mixes the
    object with its surroundings) x BORDER_WEIGHT when the image border cuts the box."""
    w = min(1.0, pixels / FULL_VIEW_PIXELS) * sharpness / (sharpness + SHARP_HALF)
    return w * (BORDER_WEIGHT if cut else 1.0)


@dataclass(frozen=True)
class ColourReading:
    """One view's colour of one object: the two most frequent basic terms, their shares of the
    n named pixels, and every term's share (COLOUR_NAMES order)."""

    name: str
    second: Optional[str]
    share: float
    second_share: float
    n: int
    shares: tuple[float, ...]

    @classmethod
    def single(cls, name: str) -> "ColourReading":
        """A reading that knows only a name (a view measured without pixels)."""
        shares = tuple(1.0 if c == name else 0.0 for c in COLOUR_NAMES)
        return cls(name, None, 1.0, 0.0, 0, shares)


def read_colour(bgr_pixels: np.ndarray, cast: Optional[Cast] = None, screen: bool = False) -> ColourReading:
    """The colour of one object in one view from its own pixels (N x 3 BGR uint8): the cast
    divided out (`apply_cast`), `surface_pixels` kept; chromatic pixels named by the survey
    (`name_pixels`), achromatic ones by their lightness relative to the frame's white and to the
    object's own lit part (`name_achromatic`)."""
    px = surface_pixels(apply_cast(bgr_pixels, cast), screen)
    if len(px) == 0:
        return ColourReading.single("grey")
    lab = bgr_to_lab(px)
    grey = is_achromatic(lab)
    names = np.empty(len(px), np.int64)
    names[~grey] = name_pixels(px[~grey])
    names[grey] = name_achromatic(lab[grey, 0], 1.0 if cast is None else cast.white)
    counts = np.bincount(names, minlength=len(COLOUR_NAMES)).astype(np.float64)
    shares = counts / counts.sum()
    first, second = np.argsort(-shares, kind="stable")[:2]
    return ColourReading(COLOUR_NAMES[first], COLOUR_NAMES[second] if shares[second] > 0 else None,
                         float(shares[first]), float(shares[second]), int(len(px)),
                         tuple(float(s) for s in shares))


def vote(readings: Sequence[ColourReading], weights: Optional[Sequence[float]] = None) -> tuple[str, Optional[str], float]:
    """(colour, second colour or None, confidence) of an object over its views.

    Each view's term shares are averaged with its weight (how well it sees the object); the
    largest mean share names the object, the next one is its second colour when it covers at
    least SECOND_MIN_SHARE and is not a shade of the first (SHADES). Shares equal to SHARE_DECIMALS
    are a tie, won by the name earlier in COLOUR_NAMES. Confidence: the weighted share of views whose own colour is the
    winner (1.0 when every good view agrees)."""
    if not readings:
        return "grey", None, 0.0
    w = np.ones(len(readings)) if weights is None else np.maximum(np.asarray(weights, np.float64), 0.0)
    if w.sum() <= 0:
        w = np.ones(len(readings))
    shares = np.array([r.shares for r in readings], np.float64)
    # to a fixed precision: shares equal but for their last bits (a white and a grey view of equal
    # weight) are a tie, and a tie goes to the name earlier in COLOUR_NAMES, not to rounding noise
    mean = np.round((w[:, None] * shares).sum(axis=0) / w.sum(), SHARE_DECIMALS)
    first, second = np.argsort(-mean, kind="stable")[:2]
    name, other = COLOUR_NAMES[first], COLOUR_NAMES[second]
    confidence = float(sum(wi for wi, r in zip(w, readings) if r.name == name) / w.sum())
    keep = mean[second] >= SECOND_MIN_SHARE and frozenset((name, other)) not in SHADES
    return name, other if keep else None, confidence
