"""Write the manifest of a sample recording (`sg3d sample NAME`): its source, licence and every
file's size and SHA-256, read from a verified local copy.

    python scripts/make_sample_manifest.py kitchen [FOLDER] [--out FILE]

FOLDER defaults to the preset's folder under ../shared/data (beside the repository); the
manifest goes to sg3d/app/data/samples/<name>.json, shipped in the wheel. The files are those of
FOLDER less the preset's `exclude` names (copies kept beside the data that the source does not
serve at that path, such as the source repository's LICENSE). Check the folder against the source
before writing: the manifest is what every download is verified against.
"""
from __future__ import annotations

import argparse
import fnmatch
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))

from sg3d.app.samples import MANIFEST_DIR, describe_folder, manifest_text  # noqa: E402

KITCHEN_COMMIT = "1e14d81c7f1c04ecc8a92a1dcd6214222d7d2c00"
KITCHEN = {
    "name": "kitchen",
    "folder": "7scenes-redkitchen",
    "title": "7-Scenes red kitchen, 1000 posed RGB-D frames (Microsoft Research)",
    "url": f"https://raw.githubusercontent.com/andyzeng/tsdf-fusion-python/{KITCHEN_COMMIT}/data/",
    "source": f"github.com/andyzeng/tsdf-fusion-python, folder data/ at commit {KITCHEN_COMMIT}",
    "licence": "7-Scenes (Microsoft Research): non-commercial research use only",
    "licence_note": "note: the 7-Scenes data (Microsoft Research; Shotton et al., CVPR 2013) is "
                    "licensed for non-commercial research use only; this is the red-kitchen "
                    "sequence as redistributed by andyzeng/tsdf-fusion-python. Using it accepts "
                    "those terms.",
}
# name -> (the manifest's metadata, names of the folder left out)
PRESETS: dict[str, tuple[dict[str, str], list[str]]] = {"kitchen": (KITCHEN, ["LICENSE*"])}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("name", choices=sorted(PRESETS))
    parser.add_argument("folder", nargs="?", type=Path, help="a verified copy (default: ../shared/data/<folder>)")
    parser.add_argument("--out", type=Path, help="manifest file (default: sg3d/app/data/samples/<name>.json)")
    args = parser.parse_args()
    meta, exclude = PRESETS[args.name]
    folder = args.folder or REPO.parent / "shared" / "data" / meta["folder"]
    if not folder.is_dir():
        sys.exit(f"no folder {folder}")
    names = [p.name for p in folder.iterdir() if p.is_file()
             and not any(fnmatch.fnmatch(p.name, pattern) for pattern in exclude)]
    files = describe_folder(folder, names)
    out = args.out or MANIFEST_DIR / f"{args.name}.json"
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(manifest_text(meta, files), encoding="utf-8")
    total = sum(size for size, _ in files.values())
    print(f"{out}: {len(files)} files, {total} bytes ({total / 1e6:.1f} MB)")


if __name__ == "__main__":
    main()
