"""Colour naming (sg3d.ingest.objects.colour) on hand-made patches: the survey model, casts, screens, votes."""
import numpy as np
import pytest

from sg3d.core.model import COLOUR_NAMES
from sg3d.ingest.objects import colour as C


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


def test_a_white_object_in_shade_relative_to_a_bright_frame_is_white():
    img, _ = scene((128, 128, 128), (1, 1, 1))
    img[:20] = 250                                              # a bright window: the frame's white
    rng = np.random.default_rng(3)
    shade = rng.uniform(150, 200, 900)                          # its body turned from the light
    lit = rng.uniform(225, 235, 100)                            # its side facing the light
    cup = np.repeat(np.concatenate([shade, lit])[:, None], 3, axis=1).astype(np.uint8)
    assert np.median(cup) < 200 and C.read_colour(cup).name != "white"   # as absolute L*, grey
    assert C.read_colour(cup, C.frame_cast(img)).name == "white"
    flat_grey = np.full((1000, 3), 128, np.uint8)               # no lit part: a grey object stays grey
    assert C.read_colour(flat_grey, C.frame_cast(img)).name == "grey"


def test_a_black_cover_under_white_print_is_two_surfaces():
    px = np.full((1000, 3), 28, np.uint8)
    px[:300] = 235                                              # the print
    reading = C.read_colour(px)
    assert (reading.name, reading.second) == ("black", "white")
    assert reading.share == pytest.approx(0.7, abs=0.02)


def test_a_faint_tint_is_named_by_lightness_and_a_clear_one_by_hue():
    grey = np.full((500, 3), (150, 146, 140), np.uint8)         # a slightly warm grey: C* about 4
    assert C.is_achromatic(C.bgr_to_lab(grey)).all() and C.read_colour(grey).name == "grey"
    wood = np.full((500, 3), (60, 95, 140), np.uint8)
    assert not C.is_achromatic(C.bgr_to_lab(wood)).any() and C.read_colour(wood).name == "brown"


def test_the_achromatic_boundary_comes_from_the_survey():
    t = C.achromatic_chroma()
    assert 8.0 < t < 30.0                                      # between the survey's greys and its colours
    terms = [COLOUR_NAMES[i] for i in C.achromatic_term(np.array([5.0, 50.0, 98.0]))]
    assert terms == ["black", "grey", "white"]
    assert C.relative_lightness(np.array([50.0]), 1.0)[0] == pytest.approx(50.0, abs=0.1)
    assert C.relative_lightness(np.array([50.0]), C.lab_luminance(50.0))[0] == pytest.approx(100.0, abs=0.1)


def test_the_light_on_an_object_is_measured_on_its_surround():
    assert C.surround_bounds((100, 100, 110, 120), 640, 480) == (80, 60, 130, 160)
    assert C.surround_bounds((0, 0, 640, 480), 640, 480) == (0, 0, 640, 480)
    img = np.full((240, 320, 3), 200, np.uint8)
    img[:, 160:] = (150, 190, 230)                              # the right half lit warm (B, G, R)
    warm = C.surround_cast(img, (230, 100, 250, 120))
    assert warm.gains[0] > warm.gains[2]                        # blue raised there...
    assert np.allclose(C.surround_cast(img, (60, 100, 80, 120)).gains, 1.0)   # ...not on the left


def test_white_patch_takes_no_cast_from_a_vivid_emitter():
    img = np.full((120, 160, 3), 170, np.uint8)                 # a neutral wall under neutral light
    img[80:, :40] = 200                                         # a white object on it
    img[:40, 100:] = (40, 120, 240)                             # fire on a screen (B, G, R): no light's white
    lit = img.reshape(-1, 3)
    top = np.percentile(lit, 99, axis=0)
    orange = C.Cast((top.max() / top).astype(np.float32), np.zeros(3, np.float32))
    assert C.read_colour(img[80:, :40].reshape(-1, 3), orange).name == "blue"   # max-RGB on every pixel
    assert len(C.white_candidates(lit)) == 120 * 160 - 40 * 60  # the fire is no white candidate
    cast = C.frame_cast(img)
    assert np.allclose(cast.gains, 1.0)
    assert C.read_colour(img[80:, :40].reshape(-1, 3), cast).name == "white"


def test_a_warm_light_still_has_its_white_candidates():
    wall = np.full((4000, 3), (150, 190, 230), np.uint8)        # a white wall under warm light: ratio 1.53
    assert len(C.white_candidates(wall)) == len(wall)
    assert C.frame_cast(wall).gains[0] > 1.3                    # blue raised: the cast is still corrected


def test_a_shaded_white_beside_a_bright_screen_is_white_when_the_screen_is_left_out():
    img = np.full((240, 320, 3), 140, np.uint8)                 # a wall in shade
    img[:100, 150:] = 235                                       # a screen showing a bright sky
    img[100:110, 150:] = 20                                     # its dark frame
    rng = np.random.default_rng(5)
    vase = np.repeat(rng.uniform(138, 150, (60, 40))[..., None], 3, axis=2).astype(np.uint8)
    img[130:190, 230:270] = vase                                # a white vase as light as the shaded wall
    box, screen = (230, 130, 270, 190), (150, 0, 320, 110)
    px = vase.reshape(-1, 3)
    assert C.read_colour(px, C.surround_cast(img, box)).name == "grey"      # the picture's white
    assert C.read_colour(px, C.surround_cast(img, box, emitters=[screen])).name == "white"
    inside = C.surround_cast(img, (200, 50, 260, 120), emitters=[screen])  # an object overlapping the
    assert inside.white > C.lab_luminance(90.0)                 # screen keeps its own pixels


# --------------------------------------------------------------------------- each threshold, on both sides

def _with(n_odd: int, odd, base=(40, 40, 160), n: int = 100) -> np.ndarray:
    """n pixels of a dull red `base`, `n_odd` of them replaced by `odd` (BGR)."""
    px = np.full((n, 3), base, np.uint8)
    px[:n_odd] = odd
    return px


def test_a_highlight_is_near_white_from_200_on_every_channel():          # SPECULAR_MIN
    assert len(C.surface_pixels(_with(10, (205, 205, 250)))) == 90
    assert len(C.surface_pixels(_with(10, (195, 195, 250)))) == 100


def test_a_highlight_has_a_channel_clipped_at_245():                     # SPECULAR_CLIP
    assert len(C.surface_pixels(_with(10, (210, 210, 247)))) == 90
    assert len(C.surface_pixels(_with(10, (210, 210, 243)))) == 100


def test_highlights_are_dropped_while_they_are_a_quarter_of_the_pixels_at_most():   # SPECULAR_MAX_SHARE
    assert len(C.surface_pixels(_with(24, (250, 250, 250)))) == 76
    assert len(C.surface_pixels(_with(26, (250, 250, 250)))) == 100


def test_a_screens_own_pixels_are_those_of_luma_90_at_most():            # SCREEN_MAX_LUMA
    assert len(C.surface_pixels(_with(50, (88, 88, 88), base=(150, 150, 150)), screen=True)) == 50
    assert len(C.surface_pixels(_with(50, (92, 92, 92), base=(150, 150, 150)), screen=True)) == 100


def test_a_screens_dark_pixels_are_kept_when_they_are_a_tenth_of_it():   # SCREEN_MIN_KEPT
    assert len(C.surface_pixels(_with(12, (20, 20, 20), base=(150, 150, 150)), screen=True)) == 12
    assert len(C.surface_pixels(_with(8, (20, 20, 20), base=(150, 150, 150)), screen=True)) == 100


def test_a_views_weight_on_hand_made_numbers():      # FULL_VIEW_PIXELS 2500, SHARP_HALF 30, BORDER_WEIGHT 0.3
    assert C.view_weight(1250, 30.0, False) == pytest.approx(0.25)
    assert C.view_weight(2600, 30.0, False) == pytest.approx(0.5)
    assert C.view_weight(5000, 90.0, False) == pytest.approx(0.75)
    assert C.view_weight(5000, 30.0, True) == pytest.approx(0.15)


def test_a_cast_gain_is_at_most_1_4():                                     # MAX_GAIN
    warm = np.full((500, 3), (100, 150, 200), np.uint8)      # blue would need 2.0
    assert C.frame_cast(warm).gains[0] == pytest.approx(1.4)
    mild = np.full((500, 3), (160, 190, 208), np.uint8)      # blue needs 1.3
    assert C.frame_cast(mild).gains[0] == pytest.approx(1.3)


def test_white_candidates_are_at_most_1_4_squared_from_neutral():          # MAX_GAIN in white_candidates
    grey = np.full((200, 3), 150, np.uint8)
    assert len(C.white_candidates(np.vstack([grey, [[100, 100, 195]]]))) == 201   # ratio 1.95
    assert len(C.white_candidates(np.vstack([grey, [[100, 100, 197]]]))) == 200   # ratio 1.97


def test_the_levels_black_point_is_at_most_40():                          # MAX_BLACK
    def black(dark):
        px = np.full((1000, 3), 200, np.uint8)
        px[:50] = dark
        return C.frame_cast(px, "levels").black[0]
    assert black(60) == pytest.approx(40)
    assert black(30) == pytest.approx(30)


def test_a_cast_needs_100_lit_pixels():                                   # MIN_CAST_PIXELS
    warm = (150, 190, 230)
    assert C.frame_cast(np.full((101, 3), warm, np.uint8)).gains[0] > 1.3
    assert np.allclose(C.frame_cast(np.full((99, 3), warm, np.uint8)).gains, 1.0)


def test_the_surround_is_sampled_on_about_1200_pixels():                  # CAST_SAMPLES
    # a neutral white frame whose every 8th pixel (what a 1200-pixel sample of 320 x 240 reads) is warm
    img = np.full((240, 320, 3), 240, np.uint8)
    img[::8, ::8] = (150, 190, 230)
    assert C.surround_cast(img, (0, 0, 320, 240)).gains[0] > 1.3


def test_a_second_colour_needs_a_quarter_of_the_object():                # SECOND_MIN_SHARE
    def reading(**shares):
        v = tuple(shares.get(c, 0.0) for c in COLOUR_NAMES)
        order = sorted(shares, key=lambda c: -shares[c])
        return C.ColourReading(order[0], order[1], shares[order[0]], shares[order[1]], 100, v)
    assert C.vote([reading(white=0.73, red=0.27)])[:2] == ("white", "red")
    assert C.vote([reading(white=0.77, red=0.23)])[:2] == ("white", None)


def test_pixels_are_named_in_cells_of_8_levels():                         # LUT_LEVELS
    assert len(C.survey_lut()) == 32 ** 3


def test_dull_chroma_is_doubled_up_to_40():                               # CHROMA_GAIN, CHROMA_CAP
    lab = np.array([[50.0, 10.0, 0.0], [50.0, 30.0, 0.0], [50.0, 50.0, 0.0]], np.float32)
    assert C.boost_chroma(lab)[:, 1] == pytest.approx([20.0, 40.0, 50.0])


def test_surface_lightness_runs_from_l_20_to_l_96():                      # SURFACE_BLACK_L, SURFACE_WHITE_L
    lab = np.array([[20.0, 0, 0], [58.0, 0, 0], [96.0, 0, 0]], np.float32)
    assert C.surface_lightness(lab)[:, 0] == pytest.approx([0.0, 50.0, 100.0])


def test_the_white_reference_is_the_99th_percentile():                    # WHITE_PERCENTILE
    def white(n_bright):
        px = np.full((1000, 3), 128, np.uint8)
        px[:n_bright] = 235
        return C.white_reference(px)
    assert white(15) > 0.7          # 1.5 % bright pixels set the white
    assert white(5) < 0.3           # 0.5 %: the grey does


def test_a_surface_is_white_when_its_lit_tenth_is():                      # LIT_PERCENTILE
    assert C.read_colour(_with(12, (235, 235, 235), base=(165, 165, 165))).name == "white"
    assert C.read_colour(_with(8, (235, 235, 235), base=(165, 165, 165))).name == "grey"


def test_shading_darkens_a_surface_four_times_at_most():                  # SHADING_RANGE
    assert C.shading_groups(np.array([0.8 / 3.5] * 50 + [0.8] * 50)) == [(0, 100)]
    assert C.shading_groups(np.array([0.8 / 4.5] * 50 + [0.8] * 50)) == [(50, 100), (0, 50)]


def test_an_object_has_three_achromatic_surfaces_at_most():               # MAX_SHADING_GROUPS
    four = np.array([0.8 / 4.5 ** k for k in (3, 2, 1, 0) for _ in range(25)])
    assert C.shading_groups(four) == [(75, 100), (50, 75), (0, 50)]


def test_a_vote_tied_but_for_the_last_bits_goes_to_the_earlier_colour_name():   # SHARE_DECIMALS
    white, grey = C.ColourReading.single("white"), C.ColourReading.single("grey")
    # weights 0.1 + 0.2 and 0.3 are equal views; their float sum differs in the last bit
    assert C.vote([grey, white], [0.1 + 0.2, 0.3])[0] == C.vote([white, grey], [0.1 + 0.2, 0.3])[0] == "white"
    assert C.vote([grey, white], [0.3 + 1e-8, 0.3])[0] == "grey"
