"""The build's config: every default written once (the flags read theirs from the configs), the
build's identity unchanged by the stage configs, and the stages timed by one decorator."""
from __future__ import annotations

import time

import pytest

from sg3d.ingest.config import METHODS, BuildConfig, DetectConfig, ObjectsConfig, RelateConfig, SelectConfig
from sg3d.ingest.detect.models import SCORE_THRESHOLD
from sg3d.ingest.select.kge import DEFAULT_T_KEY
from sg3d.ingest.select.selection import SelectionParams
from sg3d.ingest.stages import StageResult, timed


def _options(command) -> dict:
    return {p.opts[0]: p for p in command.params if p.opts and p.opts[0].startswith("--")}


def test_the_build_flags_show_and_use_the_configs_defaults():
    from sg3d.commands.build import build

    opts, select, detect = _options(build), SelectConfig(), DetectConfig()
    assert opts["--score-threshold"].default == detect.score_threshold == SCORE_THRESHOLD
    assert opts["--quality"].default == detect.quality
    assert opts["--method"].default == BuildConfig().method.name
    shown = {"--t-key": select.t_key, "--t-anchor": select.t_anchor, "--detect-fraction": select.detect_fraction,
             "--chunk-frames": BuildConfig().chunk_frames, "--score-threshold": detect.score_threshold,
             "--abir-gain": select.params.abir_gain}
    for flag, value in shown.items():
        assert f"[{value:g}]" in opts[flag].help, flag


def test_the_frames_flags_show_the_configs_defaults():
    from sg3d.commands.frames import frames_command

    opts, select = _options(frames_command), SelectConfig()
    assert f"[{select.t_key:g}]" in opts["--t-key"].help and select.t_key == DEFAULT_T_KEY
    for flag, value in (("--t-anchor", select.t_anchor), ("--abir-gain", select.params.abir_gain),
                        ("--abir-offset", select.abir_offset), ("--abir-alpha", select.abir_alpha)):
        assert f"[{value:g}]" in opts[flag].help, flag
    assert SelectConfig().params == SelectionParams()


def test_the_selection_params_are_the_select_configs():
    assert BuildConfig().selection == SelectConfig().params
    assert BuildConfig(select=SelectConfig(t_key=0.3)).selection.t_key == 0.3


def test_the_build_identity_is_the_flat_one_of_before_the_stage_configs():
    """The merge keys of a build made before the stage configs are kept (a re-run merges nothing twice)."""
    assert BuildConfig().fingerprint() == (
        '{"abir_gain": null, "chunk_frames": 3000, "detect_fraction": 0.15, "detector": "ssd-mobilenet-v2-coco", '
        '"discover": true, "method": "3d-full", "min_detect_frames": 40, "quality": "default", '
        '"score_threshold": 0.23, "t_anchor": 0.9, "t_key": 0.2}')
    assert '"method": "2d-basic"' in BuildConfig(method=METHODS["2d-basic"]).fingerprint()


@pytest.mark.parametrize("config", [BuildConfig(objects=ObjectsConfig(min_detections=3)),
                                    BuildConfig(relate=RelateConfig(vote_majority=0.7))])
def test_a_tunable_added_since_changes_the_identity_only_when_set(config):
    assert config.fingerprint() != BuildConfig().fingerprint()


def test_timed_adds_the_wall_time_under_its_phase():
    from dataclasses import dataclass

    @dataclass(frozen=True, kw_only=True)
    class Slept(StageResult):
        pass

    @timed("sleep")
    def sleep() -> Slept:
        time.sleep(0.02)
        return Slept(seconds={"sleep": 1.0, "other": 2.0})

    result = sleep()
    assert 1.02 <= result.seconds["sleep"] < 1.5 and result.seconds["other"] == 2.0
