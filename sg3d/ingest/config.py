"""What a build is told: one config class per stage of the pipeline, and `BuildConfig` over them.

Every tunable is written once, beside the measurement that chose it (the constant in its stage's
module); a config field reads that constant and carries a help line in its metadata, from which
the front ends make their flags (`sg3d.commands.config_options`), so a default shown by
`sg3d build --help` is the default a build uses. A config decides the graph, so it is part of the
build's identity (`BuildConfig.fingerprint`, the merge keys of `sg3d.ingest.pipeline.run_key`).
"""
from __future__ import annotations

import json
from dataclasses import MISSING, dataclass, field, fields
from typing import Any, Optional

from sg3d.ingest.detect.choice import DEFAULT_DETECTOR
from sg3d.ingest.detect.models import SCORE_THRESHOLD
from sg3d.ingest.objects.existence import MIN_DETECTIONS
from sg3d.ingest.relate.sdr import RELATION_PROB_THRESHOLD, VOTE_MAJORITY, VOTE_MIN_SUPPORT
from sg3d.ingest.select import coverage
from sg3d.ingest.select.abir import DEFAULT_ALPHA, DEFAULT_GAIN, DEFAULT_OFFSET
from sg3d.ingest.select.kge import DEFAULT_T_KEY
from sg3d.ingest.select.selection import BUILD_T_ANCHOR, SelectionParams

# A room-sized sequence is fused whole; longer recordings are cut into chunks of this many
# frames, each fused on its own and merged like the paper's local graphs.
DEFAULT_CHUNK_FRAMES = 3000


def tunable(default: Any, help: str, shown: Any = None) -> Any:
    """A config field: its default and the help line of its flag (`shown`: the value the help
    names where the default is None, meaning "the stage's own default")."""
    return field(default=default, metadata={"help": help, "shown": default if shown is None else shown})


@dataclass(frozen=True)
class Method:
    """Which modules run (paper Table I)."""

    name: str
    efficient: bool      # ABIR + KGE (+ coverage): only sharp, informative frames are detected
    three_d: bool        # 3-D fusion + same-node detection (else every detection is a node)
    sdr: bool            # spurious detection rejection (classes, existence, relation vote + prior)


METHODS = {
    "2d-basic": Method("2d-basic", efficient=False, three_d=False, sdr=False),
    "2d-efficient": Method("2d-efficient", efficient=True, three_d=False, sdr=False),
    "3d-basic": Method("3d-basic", efficient=False, three_d=True, sdr=False),
    "3d-efficient": Method("3d-efficient", efficient=True, three_d=True, sdr=False),
    "3d-full": Method("3d-full", efficient=True, three_d=True, sdr=True),
}
DEFAULT_METHOD = "3d-full"


@dataclass(frozen=True)
class SelectConfig:
    """Frame selection (ABIR, KGE, coverage): which frames the detector runs on."""

    abir_gain: Optional[float] = tunable(None, "ABIR gain g of Eq. 4 (the authors' code; the paper prints 30)",
                                         shown=DEFAULT_GAIN)
    abir_offset: float = tunable(DEFAULT_OFFSET, "ABIR offset b of Eq. 4")
    abir_alpha: float = tunable(DEFAULT_ALPHA, "ABIR smoothing factor alpha of Eq. 2")
    t_key: float = tunable(DEFAULT_T_KEY, "KGE keyframe overlap threshold")
    t_anchor: float = tunable(BUILD_T_ANCHOR, "KGE anchor overlap threshold (the authors' code: 0.68; see "
                                              "sg3d/ingest/select/selection.py)")
    detect_fraction: float = tunable(coverage.DEFAULT_FRACTION,
                                     "Share of the sharp frames the detector runs on (KGE frames first, then "
                                     f"new viewpoints); at least {coverage.MIN_FRAMES} frames (or all) are "
                                     "detected in any sequence")
    min_detect_frames: int = tunable(coverage.MIN_FRAMES, "Frames detected at least, in any sequence")

    @property
    def params(self) -> SelectionParams:
        """These settings as `choose_detected_frames` takes them."""
        gain = DEFAULT_GAIN if self.abir_gain is None else self.abir_gain
        return SelectionParams(abir_alpha=self.abir_alpha, abir_gain=gain, abir_offset=self.abir_offset, t_key=self.t_key,
                               t_anchor=self.t_anchor, detect_fraction=self.detect_fraction,
                               min_detect_frames=self.min_detect_frames)


@dataclass(frozen=True)
class DetectConfig:
    """Detection on the chosen frames."""

    detector: str = tunable(DEFAULT_DETECTOR, "Detector: ssd-mobilenet-v2-coco or your own ONNX model "
                                              "(labels file beside it)")
    score_threshold: float = tunable(SCORE_THRESHOLD, "Detection score threshold (any detector)")
    quality: str = tunable("default", "high: the detector also runs on 3x2 overlapping tiles of each chosen "
                                      "frame (finds smaller and farther objects, ~6x slower)")


@dataclass(frozen=True)
class ObjectsConfig:
    """Fusion and existence (SDR): which hypotheses become objects."""

    min_detections: int = tunable(MIN_DETECTIONS, "Detections an object needs (the paper's 'seen at least twice')")


@dataclass(frozen=True)
class DiscoverConfig:
    """Discovery from depth (3d-full): the room's structure and the objects no detector named."""

    enabled: bool = tunable(True, "Find unnamed objects and the room's structure from depth")
    windows: bool = tunable(False, "Find the windows too: holes in walls seen through (a walk's rooms, --rooms auto)")


@dataclass(frozen=True)
class RelateConfig:
    """Relations: voted across frames, filtered by the prior (Eq. 7)."""

    vote_majority: float = tunable(VOTE_MAJORITY, "Share of the frames a voted relation must win")
    vote_min_support: float = tunable(VOTE_MIN_SUPPORT, "Share of the co-observing frames it must hold in")
    prior_threshold: float = tunable(RELATION_PROB_THRESHOLD, "Eq. 7 probability a relation needs")


# The build's identity as first written (flat, in this order of names): a build made before the
# stage configs keeps its merge keys. A tunable added since joins it only when it is not its default.
_FINGERPRINT_FIELDS = {
    "abir_gain": ("select", "abir_gain"), "chunk_frames": (None, "chunk_frames"),
    "detect_fraction": ("select", "detect_fraction"), "detector": ("detect", "detector"),
    "discover": ("discover", "enabled"), "min_detect_frames": ("select", "min_detect_frames"),
    "quality": ("detect", "quality"), "score_threshold": ("detect", "score_threshold"),
    "t_anchor": ("select", "t_anchor"), "t_key": ("select", "t_key"),
}
STAGES = ("select", "detect", "objects", "discover", "relate")


@dataclass(frozen=True)
class BuildConfig:
    """Everything that decides which graph a build makes (and so its merge keys): the modules run
    (`method`, paper Table I), each stage's tunables, and the chunk size."""

    method: Method = METHODS[DEFAULT_METHOD]
    select: SelectConfig = SelectConfig()
    detect: DetectConfig = DetectConfig()
    objects: ObjectsConfig = ObjectsConfig()
    discover: DiscoverConfig = DiscoverConfig()
    relate: RelateConfig = RelateConfig()
    chunk_frames: int = tunable(DEFAULT_CHUNK_FRAMES, "Fuse and merge the sequence in chunks of this many frames")

    @property
    def selection(self) -> SelectionParams:
        """The frame-selection part of this config."""
        return self.select.params

    def fingerprint(self) -> str:
        d: dict[str, Any] = {"method": self.method.name}
        for name, (stage, attr) in _FINGERPRINT_FIELDS.items():
            d[name] = getattr(getattr(self, stage) if stage else self, attr)
        known = {(stage, attr) for stage, attr in _FINGERPRINT_FIELDS.values()}
        for stage in STAGES:
            for f in fields(getattr(self, stage)):
                value = getattr(getattr(self, stage), f.name)
                if (stage, f.name) not in known and value != f.default:
                    d[f"{stage}.{f.name}"] = value
        return json.dumps(d, sort_keys=True)


def default_of(config: type, name: str) -> Any:
    """The default of field `name` of a config class."""
    f = next(f for f in fields(config) if f.name == name)
    assert f.default is not MISSING
    return f.default


def help_of(config: type, name: str) -> str:
    """Field `name`'s help line with the default it stands for, as a flag shows it: "... [0.2]"."""
    f = next(f for f in fields(config) if f.name == name)
    shown = f.metadata["shown"]
    return f"{f.metadata['help']} [{shown:g}]." if isinstance(shown, (int, float)) and not isinstance(shown, bool) \
        else f"{f.metadata['help']} [{shown}]."
