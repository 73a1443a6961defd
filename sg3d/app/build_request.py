"""A build's request and the checks made before the store starts (`prepare`)."""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Optional

from sg3d.core.errors import Sg3dError

if TYPE_CHECKING:
    from sg3d.ingest.config import BuildConfig


class BuildError(Sg3dError, ValueError):
    """Bad input to a build (the front end shows it as one line)."""


@dataclass(frozen=True)
class BuildRequest:
    sequence: Path
    room: str
    building: str = "default"
    layout: Optional[str] = None
    start: int = 0
    stop: Optional[int] = None
    transform_file: Optional[Path] = None
    align_to: Optional[str] = None
    shared_frame: bool = False
    bag_options: Optional[dict] = None  # ROS bags: `sg3d.ingest.readers.bag.BagOptions` fields
    estimate_poses: bool = False        # ignore the recording's poses and estimate them
    trajectory_out: Optional[Path] = None  # write the estimated trajectory here (TUM format)
    wait: bool = False                  # wait for another writer of the room instead of refusing
    rooms: Optional[str] = None         # "auto": find the rooms of the walk too (`sg3d.app.places`)


def check_names(room: str, building: str, error: type[Exception] = BuildError) -> None:
    """`error` unless both can name a room and a building (`sg3d.app.bounds.name_problem`: the rule
    the CLI and `POST /ingest` apply; a room's id is building/room)."""
    from sg3d.app.bounds import name_problem

    problem = name_problem(room, "room") or name_problem(building, "building")
    if problem:
        raise error(problem)


def validate(req: BuildRequest) -> None:
    check_names(req.room, req.building)
    if req.rooms not in (None, "auto"):
        raise BuildError(f"--rooms {req.rooms}: only 'auto' (find the rooms of the walk) is known")
    if sum(map(bool, (req.transform_file, req.align_to, req.shared_frame))) > 1:
        raise BuildError("give at most one of --transform, --align-to and --shared-frame")
    if req.trajectory_out is not None and not Path(req.trajectory_out).expanduser().parent.is_dir():
        raise BuildError(f"--trajectory-out {req.trajectory_out}: no such folder {Path(req.trajectory_out).parent}")
    if req.start < 0 or (req.stop is not None and req.stop <= req.start):
        raise BuildError(f"empty frame range: --start {req.start} --stop {req.stop} "
                         f"(stop must be greater than start, start at least 0)")


def check_frame_selection_options(method: str, given: list[str]) -> None:
    """The basic presets (2d-basic, 3d-basic: paper Table I without the efficient modules) detect
    every frame, so ABIR and KGE never run and their options would change nothing: refuse them
    rather than accept a setting that is silently ignored."""
    from sg3d.ingest.config import METHODS

    if given and not METHODS[method].efficient:
        raise BuildError(f"{', '.join(given)} tune{'s' if len(given) == 1 else ''} ABIR/KGE frame selection, "
                         f"which --method {method} does not run (it detects every frame); "
                         f"drop {'it' if len(given) == 1 else 'them'} or use an efficient preset")


def check_detector(settings: BuildConfig) -> Any:
    """The build's detector; an unknown detector, a missing ONNX labels file or a recogniser that
    cannot run offline is refused before anything starts (nothing is loaded here)."""
    from sg3d.ingest.detect.choice import detector_for

    try:
        return detector_for(settings.detect.detector, settings.detect.score_threshold, tiles=settings.detect.quality == "high")
    except (ValueError, FileNotFoundError, RuntimeError) as exc:
        raise BuildError(str(exc))


@dataclass(frozen=True)
class PreparedBuild:
    """A checked build request with what it needs that no store holds: the detector and the
    room-to-building transform read from `--transform`."""
    req: BuildRequest
    settings: BuildConfig
    detector: Any
    placement: Optional[Any] = None  # 4x4 array


def prepare(req: BuildRequest, settings: BuildConfig, detector: Any = None, selection_given: tuple[str, ...] = ()) -> PreparedBuild:
    """Check everything a build can check before the store starts, in this order: the request,
    the frame-selection options given (`selection_given`: their flags), the detector
    (`check_detector`), the transform file (read before the long build, to fail early)."""
    from sg3d.app.places import walk_settings

    validate(req)
    settings = walk_settings(settings, req.rooms)
    check_frame_selection_options(settings.method.name, list(selection_given))
    detector = detector if detector is not None else check_detector(settings)
    placement = None
    if req.transform_file is not None:
        from sg3d.graphdb.building import TransformError, load_transform

        try:
            placement = load_transform(req.transform_file)
        except TransformError as exc:
            raise BuildError(str(exc))
    return PreparedBuild(req, settings, detector, placement)
