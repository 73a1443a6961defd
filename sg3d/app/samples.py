"""Sample recordings (`sg3d sample NAME`): a verified copy of a public RGB-D recording, found
locally or downloaded once into the user cache, so that `sg3d build "$(sg3d sample kitchen)"`
works on any machine.

A sample is defined by a manifest (`sg3d/app/data/samples/NAME.json`, written by
`scripts/make_sample_manifest.py`): where the files come from, their licence, and every file's
size and SHA-256. A copy is used only when every file verifies against the manifest:

1. a local copy: `$SG3D_SAMPLES/<folder>`, else `../shared/data/<folder>` from the current
   directory (where a checkout of this project keeps its data); it is used in place, not copied;
2. the cache: `$SG3D_CACHE/samples/<folder>`, else the same under the user cache directory;
3. a download from the manifest's URL (or `$SG3D_SAMPLE_URL/<folder>/`, a mirror of the
   `../shared/data` layout) into `<folder>.partial` beside the cache folder: each file is written
   as `NAME.part`, checked against its SHA-256 and only then renamed, and the folder is renamed to
   `<folder>` once every file is there, so a killed download never leaves a folder that looks
   complete and the next run fetches only what is missing.

Extra manifests (e.g. a test's five-file sample) come from `$SG3D_SAMPLE_MANIFEST` (paths joined
by the OS path separator) or the `manifests` parameter.
"""
from __future__ import annotations

import hashlib
import http.client
import json
import os
import shutil
import ssl
import threading
import urllib.error
import urllib.request
from concurrent.futures import FIRST_EXCEPTION, Future, ThreadPoolExecutor, wait
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable, Iterable, Mapping, Optional, Protocol, Sequence
from urllib.parse import quote

from sg3d.app.errors import AppError
from sg3d.core.errors import Sg3dError
from sg3d.core.stored import Row

MANIFEST_DIR = Path(__file__).resolve().parent / "data" / "samples"
MANIFEST_ENV = "SG3D_SAMPLE_MANIFEST"    # extra manifest files, os.pathsep-separated
URL_ENV = "SG3D_SAMPLE_URL"              # a mirror: files at <url>/<folder>/<file>
LOCAL_ENV = "SG3D_SAMPLES"               # a folder holding sample folders, like ../shared/data
CACHE_ENV = "SG3D_CACHE"                 # sg3d's cache folder; samples go in <cache>/samples
WORKERS = 8                              # parallel connections of one download
ATTEMPTS = 4                             # tries per file before a network failure is final
TIMEOUT_S = 60.0                         # per connection, connect and each read
CHUNK = 1 << 16
RETRY_STATUS = frozenset({408, 425, 429, 500, 502, 503, 504})


class SampleError(AppError):
    """An unknown sample, a file that does not verify, or a download that failed."""


class _Mismatch(SampleError):
    """A downloaded file differs from the manifest: asking the same source again gets the same file."""


@dataclass(frozen=True)
class Sample:
    """One sample recording as its manifest defines it."""
    name: str
    folder: str                            # the folder's name, locally and in the cache
    title: str
    url: str                               # the folder the files are downloaded from
    source: str                            # where the files come from, for people
    licence: str                           # one line
    licence_note: str                      # printed before the first download
    files: Mapping[str, tuple[int, str]] = field(repr=False)   # name -> (size, sha256)

    @property
    def size(self) -> int:
        return sum(size for size, _ in self.files.values())


@dataclass(frozen=True)
class Found:
    """Where `locate_sample` found (or put) a verified copy."""
    sample: Sample
    path: Path
    origin: str                            # "local", "cache" or "download"
    downloaded_bytes: int = 0


class Progress(Protocol):
    """What a download reports its bytes to (the CLI draws a progress bar with it)."""

    def start(self, total: int, completed: int) -> None: ...

    def advance(self, nbytes: int) -> None: ...


class _Quiet:
    def start(self, total: int, completed: int) -> None:
        pass

    def advance(self, nbytes: int) -> None:
        pass


# --------------------------------------------------------------------------- manifests

def load_manifest(path: Path) -> Sample:
    """A sample from its manifest file (JSON; see scripts/make_sample_manifest.py)."""
    try:
        data = json.loads(Path(path).read_text(encoding="utf-8"))
        files = {str(name): (int(size), str(digest).lower()) for name, (size, digest) in data["files"].items()}
        odd = [n for n in files if n in ("", ".", "..") or "/" in n or "\\" in n or n.endswith((".part", ".partial"))]
        if odd or "/" in data["folder"] or data["folder"] in ("", ".", ".."):
            raise ValueError(f"file and folder names must be plain names (not {(odd or [data['folder']])[0]!r})")
        return Sample(name=data["name"], folder=data["folder"], title=data["title"], url=data["url"],
                      source=data.get("source", data["url"]), licence=data["licence"],
                      licence_note=data.get("licence_note", data["licence"]), files=files)
    except (OSError, ValueError, KeyError, TypeError) as exc:
        raise SampleError(f"cannot read the sample manifest {path}: {exc}") from None


def manifest_paths(manifests: Optional[Sequence[Path]] = None) -> list[Path]:
    """The packaged manifests, then `manifests` (or those named by $SG3D_SAMPLE_MANIFEST)."""
    if manifests is None:
        manifests = [Path(p).expanduser() for p in os.environ.get(MANIFEST_ENV, "").split(os.pathsep) if p]
    return sorted(MANIFEST_DIR.glob("*.json")) + list(manifests)


def known_samples(manifests: Optional[Sequence[Path]] = None) -> dict[str, Sample]:
    """Every sample by name; a later manifest of the same name replaces an earlier one."""
    samples = (load_manifest(p) for p in manifest_paths(manifests))
    return {s.name: s for s in samples}


def get_sample(name: str, manifests: Optional[Sequence[Path]] = None) -> Sample:
    samples = known_samples(manifests)
    if name not in samples:
        raise SampleError(f"no sample named {name!r} (known: {', '.join(sorted(samples)) or 'none'})")
    return samples[name]


def describe_folder(folder: Path, names: Optional[Iterable[str]] = None) -> dict[str, tuple[int, str]]:
    """name -> (size, sha256) of the files of `folder` (or of `names` in it), sorted by name."""
    chosen = sorted(names) if names is not None else sorted(p.name for p in Path(folder).iterdir() if p.is_file())
    return {name: file_digest(Path(folder) / name) for name in chosen}


def manifest_text(meta: Mapping[str, str], files: Mapping[str, tuple[int, str]]) -> str:
    """A manifest's JSON: the metadata (name, folder, title, url, source, licence, licence_note),
    then one line per file, `"name": [size, "sha256"]`, sorted by name."""
    head = json.dumps(dict(meta), indent=2, ensure_ascii=False)[:-2]      # without the closing "\n}"
    rows = ",\n".join(f"    {json.dumps(name)}: [{size}, {json.dumps(digest)}]"
                      for name, (size, digest) in sorted(files.items()))
    return f'{head},\n  "files": {{\n{rows}\n  }}\n}}\n'


# --------------------------------------------------------------------------- verification

def file_digest(path: Path) -> tuple[int, str]:
    digest, size = hashlib.sha256(), 0
    with open(path, "rb") as f:
        while block := f.read(1 << 20):
            digest.update(block)
            size += len(block)
    return size, digest.hexdigest()


def _verifies(path: Path, expected: tuple[int, str]) -> bool:
    try:
        return path.stat().st_size == expected[0] and file_digest(path) == expected
    except OSError:
        return False


def unverified(folder: Path, sample: Sample, names: Optional[Iterable[str]] = None) -> list[str]:
    """The files of the sample (or of `names`) that are missing from `folder` or differ from the
    manifest, sorted; files the manifest does not name are ignored."""
    chosen = sorted(sample.files if names is None else names)
    with ThreadPoolExecutor(4) as pool:      # hashlib lets go of the GIL over large buffers
        ok = list(pool.map(lambda n: _verifies(Path(folder) / n, sample.files[n]), chosen))
    return [name for name, good in zip(chosen, ok) if not good]


# --------------------------------------------------------------------------- where copies live

def cache_folder(sample: Sample, cache: Optional[Path] = None) -> Path:
    """`<cache>/samples/<folder>`: $SG3D_CACHE, else the user cache directory."""
    if cache is None:
        from platformdirs import user_cache_dir

        cache = Path(os.environ.get(CACHE_ENV) or user_cache_dir("sg3d", appauthor=False)).expanduser()
    return Path(cache) / "samples" / sample.folder


def local_candidates(sample: Sample, roots: Optional[Sequence[Path]] = None) -> list[Path]:
    """Where a local copy may be: `<root>/<folder>` for $SG3D_SAMPLES, then ../shared/data from
    the current directory (absolute paths, `..` folded)."""
    if roots is None:
        roots = ([Path(os.environ[LOCAL_ENV]).expanduser()] if os.environ.get(LOCAL_ENV) else []) \
            + [Path.cwd() / ".." / "shared" / "data"]
    return [Path(os.path.abspath(Path(root) / sample.folder)) for root in roots]


def sample_url(sample: Sample, base_url: Optional[str] = None) -> str:
    """The folder URL the files come from, ending in '/': $SG3D_SAMPLE_URL/<folder>/ (a mirror of
    the ../shared/data layout) when set, else the manifest's."""
    base = base_url if base_url is not None else os.environ.get(URL_ENV)
    url = f"{base.rstrip('/')}/{quote(sample.folder)}/" if base else sample.url
    return url if url.endswith("/") else url + "/"


def sample_listing(manifests: Optional[Sequence[Path]] = None, cache: Optional[Path] = None) -> list[Row]:
    """The samples for `sg3d sample --list`: name, title, files, bytes, licence, source, and the
    folder a copy is already in (not verified here) or None."""
    rows = []
    for sample in sorted(known_samples(manifests).values(), key=lambda s: s.name):
        where = [p for p in [*local_candidates(sample), cache_folder(sample, cache)] if p.is_dir()]
        rows.append({"name": sample.name, "title": sample.title, "files": len(sample.files), "bytes": sample.size,
                     "licence": sample.licence, "source": sample.source,
                     "present": str(where[0]) if where else None})
    return rows


# --------------------------------------------------------------------------- finding a copy

@dataclass(frozen=True)
class Places:
    """Where samples are looked for (None: the defaults of the module's docstring): the manifests,
    the cache folder, the download server, the folders a local copy may lie in."""

    manifests: Optional[Sequence[Path]] = None
    cache: Optional[Path] = None
    base_url: Optional[str] = None
    local_roots: Optional[Sequence[Path]] = None


def locate_sample(name: str, places: Places = Places(), progress: Optional[Progress] = None,
                  notice: Callable[[str], None] = lambda _: None) -> Found:
    """A verified copy of sample `name`: a local one, the cache's, or a fresh download (see the
    module's docstring). `notice` gets one-line messages for the user (a local copy that does not
    verify, the licence note before downloading); SampleError when it cannot be had."""
    manifests, cache, base_url, local_roots = places.manifests, places.cache, places.base_url, places.local_roots
    sample = get_sample(name, manifests)
    for candidate in local_candidates(sample, local_roots):
        if candidate.is_dir():
            bad = unverified(candidate, sample)
            if not bad:
                return Found(sample, candidate, "local")
            notice(f"the local copy {candidate} is not used: {_bad_summary(bad, sample)}")
    final = cache_folder(sample, cache)
    if final.is_dir():
        bad = unverified(final, sample)
        if not bad:
            return Found(sample, final, "cache")
        notice(f"repairing the cached copy {final}: {_bad_summary(bad, sample)}")
        partial = _partial(final)
        if partial.exists():
            shutil.rmtree(partial)
        final.rename(partial)                  # its good files are kept; the bad ones fetched again
    downloaded = download_sample(sample, final, url=sample_url(sample, base_url), progress=progress, notice=notice)
    return Found(sample, final, "download", downloaded)


def _bad_summary(bad: list[str], sample: Sample) -> str:
    return f"{len(bad)} of {len(sample.files)} files missing or different (first: {bad[0]})"


def _partial(final: Path) -> Path:
    return final.with_name(final.name + ".partial")


# --------------------------------------------------------------------------- downloading

def download_sample(sample: Sample, final: Path, *, url: str, progress: Optional[Progress] = None,
                    notice: Callable[[str], None] = lambda _: None, workers: int = WORKERS) -> int:
    """Download the sample's files from the folder `url` into `final` (see the module docstring);
    files already verified in `<final>.partial` are kept. Returns the bytes downloaded."""
    progress = progress or _Quiet()
    partial = _partial(final)
    partial.mkdir(parents=True, exist_ok=True)
    for stale in partial.glob("*.part"):
        stale.unlink()
    present = [n for n in sample.files if (partial / n).exists()]
    bad = unverified(partial, sample, present)
    for name in bad:
        (partial / name).unlink()
    kept = set(present) - set(bad)
    todo = sorted(n for n in sample.files if n not in kept)
    todo_bytes = sum(sample.files[n][0] for n in todo)
    if todo:
        notice(sample.licence_note)
        notice(f"downloading {len(todo)} file{'' if len(todo) == 1 else 's'} ({_size(todo_bytes)}) of sample "
               f"{sample.name!r} from {url} into {final}")
    progress.start(todo_bytes, 0)          # the bar counts what this run fetches, as the line above says
    try:
        _fetch_all(todo, sample, partial, url, progress, workers)
    except SampleError as exc:
        raise SampleError(_failed(exc, sample, partial, url)) from None
    missing = [n for n in sample.files if not (partial / n).is_file()]
    if missing:                                # not expected: every fetched file was verified
        raise SampleError(f"the download of {sample.name!r} is incomplete ({len(missing)} files missing)")
    partial.rename(final)
    return todo_bytes


def _failed(exc: SampleError, sample: Sample, partial: Path, url: str) -> str:
    """The one line a failed download ends with: what failed, what is kept (the `.partial` folder
    goes when nothing verified is in it) and the way out."""
    kept = [n for n in sample.files if (partial / n).is_file()]
    if not kept:
        shutil.rmtree(partial, ignore_errors=True)
    if isinstance(exc, _Mismatch):
        return (f"{exc}; {url} serves files that differ from the sample's manifest: fix that mirror, "
                f"or unset {URL_ENV} (or point it at another mirror)")
    way_out = (f"without network, point ${URL_ENV} at a mirror of ../shared/data, or put a copy in "
               f"${LOCAL_ENV}/{sample.folder} or ../shared/data/{sample.folder}")
    if kept:
        return f"{exc}; the {len(kept)} files verified so far are kept: run again to resume ({way_out})"
    return f"{exc}; {way_out}"


def _fetch_all(names: list[str], sample: Sample, folder: Path, url: str, progress: Progress, workers: int) -> None:
    """Fetch `names` with at most `workers` connections; the first failure stops the rest (their
    `.part` files are removed) and is raised."""
    if not names:
        return
    stop = threading.Event()
    pool = ThreadPoolExecutor(max(1, min(workers, len(names))))
    futures: list[Future] = [pool.submit(_fetch_file, url + quote(n), folder / n, sample.files[n], progress, stop)
                             for n in names]
    try:
        wait(futures, return_when=FIRST_EXCEPTION)
        errors = [f.exception() for f in futures if f.done() and not f.cancelled()]
        first = next((e for e in errors if e is not None), None)
        if first is not None:
            raise first
    except BaseException:
        stop.set()
        raise
    finally:
        pool.shutdown(wait=True, cancel_futures=True)


def _fetch_file(url: str, dest: Path, expected: tuple[int, str], progress: Progress, stop: threading.Event) -> None:
    """One file into `dest`, through `dest.part`, retried on network failures; a body that does
    not match its size and SHA-256 is deleted and refused (SampleError, no retry)."""
    part = dest.with_name(dest.name + ".part")
    got, digest = 0, ""
    for attempt in range(ATTEMPTS):
        try:
            got, digest = _stream(url, part, progress, stop)
            break
        except _Retry as exc:
            progress.advance(-exc.got)         # the bar counts each byte once
            part.unlink(missing_ok=True)
            if attempt == ATTEMPTS - 1:
                raise SampleError(f"cannot download {url}: {exc.reason} (tried {ATTEMPTS} times)") from None
            if stop.wait(min(8.0, 0.5 * 2 ** attempt)):
                raise _Stopped(url) from None
        except BaseException:
            part.unlink(missing_ok=True)
            raise
    if (got, digest) != expected:
        part.unlink(missing_ok=True)
        what = "size" if got != expected[0] else "SHA-256"
        raise _Mismatch(f"{dest.name} from {url} does not match the sample's {what} (expected "
                          f"{expected[0]} bytes, sha256 {expected[1][:16]}..., got {got} bytes, sha256 "
                          f"{digest[:16]}...); the file was deleted")
    os.replace(part, dest)


class _Retry(Sg3dError):
    def __init__(self, reason: str, got: int) -> None:
        super().__init__(reason)
        self.reason, self.got = reason, got


class _Stopped(Sg3dError):
    """Another file failed: this one stops between two chunks."""


def _stream(url: str, part: Path, progress: Progress, stop: threading.Event) -> tuple[int, str]:
    """GET `url` into `part`, hashing and reporting as it goes: (bytes, sha256). Network failures
    worth another try raise _Retry (with the bytes already reported); others SampleError."""
    digest, got = hashlib.sha256(), 0
    request = urllib.request.Request(url, headers={"User-Agent": "sg3d-sample"})
    try:
        with urllib.request.urlopen(request, timeout=TIMEOUT_S) as response, open(part, "wb") as out:
            while chunk := response.read(CHUNK):
                if stop.is_set():
                    raise _Stopped(url)
                out.write(chunk)
                digest.update(chunk)
                got += len(chunk)
                progress.advance(len(chunk))
    except urllib.error.HTTPError as exc:
        if exc.code in RETRY_STATUS:
            raise _Retry(f"HTTP {exc.code} {exc.reason}", got) from None
        raise SampleError(f"cannot download {url}: HTTP {exc.code} {exc.reason}") from None
    except (urllib.error.URLError, http.client.HTTPException, ConnectionError, TimeoutError, ssl.SSLError) as exc:
        reason = getattr(exc, "reason", None) or exc
        raise _Retry(f"{type(exc).__name__}: {reason}", got) from None
    return got, digest.hexdigest()


def _size(nbytes: int) -> str:
    """Bytes as the progress bar shows them (decimal units)."""
    if nbytes < 1000:
        return f"{nbytes} bytes"
    return f"{nbytes / 1e3:.1f} kB" if nbytes < 1_000_000 else f"{nbytes / 1e6:.1f} MB"
