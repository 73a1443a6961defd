"""Colour naming (ingest.colour) on hand-made patches: the survey model, casts, screens, votes."""
import numpy as np
import pytest

from ingest import colour as C
from ingest.model import COLOUR_NAMES


def scene(patch, light, size=(120, 160)):
    """A frame of three greys and one patch, lit by per-channel (B, G, R) light."""
    img = np.zeros(size + (3,), np.float32)
    img[:] = 128
    img[:60, :80] = 60
    img[60:, 80:] = 180
    img[40:80, 60:100] = patch
    img = np.clip(img * np.asarray(light, np.float32), 0, 255).astype(np.uint8)
    return img, img[40:80, 60:100].reshape(-1, 3)


@pytest.mark.parametrize("name,term", [
    ("xkcd:blue green", "green"), ("xkcd:greenish blue", "blue"), ("xkcd:reddish brown", "brown"),
    ("xkcd:light gray", "grey"), ("xkcd:navy", "blue"), ("xkcd:maroon", "red"), ("xkcd:teal", None),
    ("xkcd:blue with a hint of purple", "blue"), ("xkcd:pale grey", "white"),
])
def test_survey_names_take_their_head_words_basic_term(name, term):
    assert C.basic_term(name) == term


def test_every_basic_term_has_survey_colours():
    _, terms = C.survey_colours()
    assert set(np.unique(terms)) == set(range(len(COLOUR_NAMES)))


def test_dark_green_under_warm_light_is_green():
    img, px = scene((40, 90, 30), (0.75, 0.95, 1.25))
    assert C.read_colour(px, C.frame_cast(img)).name == "green"


def test_a_grey_world_corrected_white_is_white():
    img, px = scene((250, 250, 250), (1.0, 0.9, 0.8))          # cool light (B, G, R): the white looks blue
    assert C.read_colour(px).name != "white"
    gains = C.frame_cast(img, "grey-world")
    assert gains.gains[2] > gains.gains[0]                      # red is boosted, blue is not
    assert C.read_colour(px, gains).name == "white"


def test_cast_methods_are_checked():
    img, _ = scene((128, 128, 128), (1, 1, 1))
    with pytest.raises(ValueError, match="unknown colour-cast method"):
        C.frame_cast(img, "purple-world")
    assert np.allclose(C.frame_cast(img, "none").gains, 1)


def test_a_dark_tv_screen_with_a_bright_reflection_is_black():
    px = np.full((1000, 3), (18, 16, 15), np.uint8)
    px[:150] = (252, 252, 252)                                  # the window's reflection
    assert C.read_colour(px, screen=True).name == "black"
    assert C.read_colour(px).name == "black"                    # a highlight minority is dropped anyway


def test_a_screen_showing_bright_content_is_read_by_its_frame():
    px = np.full((1000, 3), (20, 18, 16), np.uint8)
    px[:700] = (240, 220, 90)                                   # a bright blue picture
    assert C.read_colour(px).name != "black"
    assert C.read_colour(px, screen=True).name == "black"
    assert C.is_screen("tv") and not C.is_screen("cup")


def test_vote_keeps_a_clear_second_colour_and_weighs_views():
    def reading(**shares):
        v = tuple(shares.get(c, 0.0) for c in COLOUR_NAMES)
        order = sorted(shares, key=lambda c: -shares[c])
        return C.ColourReading(order[0], order[1] if len(order) > 1 else None, shares[order[0]],
                               shares[order[1]] if len(order) > 1 else 0.0, 100, v)
    cup = [reading(white=0.7, red=0.3), reading(white=0.65, red=0.35), reading(brown=0.9, white=0.1)]
    name, second, confidence = C.vote(cup, [1.0, 1.0, 0.05])
    assert (name, second) == ("white", "red") and confidence > 0.9
    name, second, _ = C.vote(cup[2:], [1.0])
    assert (name, second) == ("brown", None)
    assert C.vote([]) == ("grey", None, 0.0)


def test_view_weight_prefers_big_sharp_uncut_views():
    big = C.view_weight(5000, 100.0, False)
    assert big > C.view_weight(500, 100.0, False)
    assert big > C.view_weight(5000, 5.0, False)
    assert big > C.view_weight(5000, 100.0, True)
    assert 0.0 <= C.view_weight(0, 0.0, True) <= big <= 1.0


def test_name_pixels_is_a_lookup_over_any_pixel_array():
    rng = np.random.default_rng(1)
    img = rng.integers(0, 256, (30, 40, 3), dtype=np.uint8)
    names = C.name_pixels(img)
    assert names.shape == (1200,) and names.min() >= 0 and names.max() < len(COLOUR_NAMES)
    assert COLOUR_NAMES[C.name_pixels(np.array([[0, 0, 0]], np.uint8))[0]] == "black"
    assert COLOUR_NAMES[C.name_pixels(np.array([[0, 0, 200]], np.uint8))[0]] == "red"


def test_a_shade_of_the_first_colour_is_no_second_colour():
    def reading(**shares):
        v = tuple(shares.get(c, 0.0) for c in COLOUR_NAMES)
        order = sorted(shares, key=lambda c: -shares[c])
        return C.ColourReading(order[0], order[1], shares[order[0]], shares[order[1]], 100, v)
    assert C.vote([reading(white=0.55, grey=0.45)])[:2] == ("white", None)      # a shaded white
    assert C.vote([reading(black=0.55, white=0.45)])[:2] == ("black", "white")  # a black-and-white magazine
    assert C.vote([reading(white=0.8, red=0.2)])[:2] == ("white", None)         # too little to name
