"""A build's checks before the store starts (`sg3d.app.build.prepare`): each refusal one BuildError,
the detector built once and handed on (no store, no frames read)."""
from __future__ import annotations

from pathlib import Path

import pytest

from sg3d.app.build import BuildError, BuildRequest, BuildSummary, prepare
from sg3d.ingest.config import METHODS, BuildConfig, DetectConfig

REQUEST = BuildRequest(sequence=Path("unused-sequence"), room="kitchen")


def test_prepare_builds_the_detector_once_and_hands_it_on():
    prepared = prepare(REQUEST, BuildConfig())
    assert prepared.detector is not None and prepared.req is REQUEST and prepared.placement is None
    given = prepared.detector
    assert prepare(REQUEST, BuildConfig(), detector=given).detector is given


@pytest.mark.parametrize("request_, settings, given, message", [
    (BuildRequest(Path("s"), "kitchen", start=5, stop=5), BuildConfig(), (), "empty frame range"),
    (REQUEST, BuildConfig(method=METHODS["3d-basic"]), ("--t-key",), "does not run"),
    (REQUEST, BuildConfig(detect=DetectConfig(detector="absent-model.onnx")), (), "labels file"),
    (BuildRequest(Path("s"), "kitchen", transform_file=Path("absent-transform.txt")), BuildConfig(), (), "absent"),
    (BuildRequest(Path("s"), "kitchen", rooms="manual"), BuildConfig(), (), "only 'auto'"),
])
def test_prepare_refuses_bad_input_with_one_build_error(request_, settings, given, message):
    with pytest.raises(BuildError, match=message):
        prepare(request_, settings, selection_given=given)


def test_the_summary_reads_like_its_json():
    fields = dict(sequence="s", layout="7scenes", room="kitchen", building="default", method="3d-full",
                  quality="default", detector="ssd", interrupted=False, up=[0.0, 0.0, 1.0],
                  frames={"read": 3}, hypotheses={}, from_depth={}, graph={"chunks": 1}, seconds={"total": 1.0},
                  input_frames_per_second=3.0, key="k", scan="k@0-3", placement=None, poses={"source": "given"},
                  floor="not seen", rooms_found=None)
    summary = BuildSummary(**fields)
    assert summary.as_dict() == fields and list(summary.as_dict()) == list(fields)
    assert summary["graph"]["chunks"] == 1 and summary.get("placement") is None
