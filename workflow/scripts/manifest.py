"""The shoot manifest: one CSV row per take (docs/shoot.md, "Manifest").

Columns (a header row names them; order is free; lines starting with '#' are comments):
  take     id of the take: letters, digits, '.', '_' and '-'; unique in the manifest
  actor    who performs it (same character set); each actor is calibrated once
  source   the take: a video file or an image folder
  layout   a marker layout JSON, or 'markerless' for a bare face (dlib landmarks)
  camera   camera intrinsics (OpenCV FileStorage), or empty for rostro's default
  neutral  the actor's neutral take (calibrated by 'rostro calibrate actor'), or an actor
           profile '.json' used as it is
  options  extra 'rostro capture' options for this take, e.g. '--method seed2d' (may be empty)
  seconds  optional: the take's length, to size the cluster time limit (empty: the config's
           take_seconds)

Relative paths are relative to the manifest's folder. Every row of one actor must give the
same layout, camera and neutral. Errors name the manifest, line and column.
"""

import csv
import os
import re
import shlex
from dataclasses import dataclass, field

REQUIRED = ("take", "actor", "source", "layout", "neutral")
OPTIONAL = ("camera", "options", "seconds")
ID = re.compile(r"^[A-Za-z0-9][A-Za-z0-9._-]*$")


class ManifestError(Exception):
    pass


@dataclass
class Take:
    take: str
    actor: str
    source: str
    layout: str  # absolute path, or "markerless"
    camera: str  # absolute path or ""
    neutral: str  # absolute path
    options: list = field(default_factory=list)
    seconds: float = 0.0  # 0: unknown
    line: int = 0

    @property
    def markerless(self):
        return self.layout == "markerless"

    def tracker_args(self):
        return ["--markerless"] if self.markerless else ["--layout", self.layout]


@dataclass
class Actor:
    name: str
    layout: str
    camera: str
    neutral: str
    line: int

    @property
    def has_profile(self):
        """True when the manifest names a ready profile instead of a neutral take."""
        return self.neutral.endswith(".json")

    def calibrate_args(self):
        args = ["--markerless"] if self.layout == "markerless" else ["--layout", self.layout]
        if self.camera:
            args += ["--camera", self.camera]
        return args


def read(path):
    """Takes of the manifest at `path`, in its order, as a dict id -> Take."""
    base = os.path.dirname(os.path.abspath(path))

    def where(line, column=None):
        return f"{path}: line {line}" + (f", column '{column}'" if column else "")

    def resolve(value):
        return value if os.path.isabs(value) else os.path.normpath(os.path.join(base, value))

    try:
        with open(path, newline="", encoding="utf-8") as f:
            lines = [(n, text) for n, text in enumerate(f, 1)
                     if text.strip() and not text.lstrip().startswith("#")]
    except OSError as e:
        raise ManifestError(f"{path}: cannot read the manifest: {e.strerror}") from None
    if not lines:
        raise ManifestError(f"{path}: no header row (expected columns {', '.join(REQUIRED)})")
    rows = list(csv.reader(text for _, text in lines))
    header = [h.strip() for h in rows[0]]
    missing = [c for c in REQUIRED if c not in header]
    if missing:
        raise ManifestError(f"{where(lines[0][0])}: header lacks column(s) {', '.join(missing)}")
    unknown = [c for c in header if c not in REQUIRED + OPTIONAL]
    if unknown:
        raise ManifestError(f"{where(lines[0][0])}: unknown column(s) {', '.join(unknown)} "
                            f"(known: {', '.join(REQUIRED + OPTIONAL)})")
    takes = {}
    for (line, _), row in zip(lines[1:], rows[1:]):
        if len(row) != len(header):
            raise ManifestError(f"{where(line)}: {len(row)} fields, the header has {len(header)}")
        cell = {h: v.strip() for h, v in zip(header, row)}
        for c in REQUIRED:
            if not cell[c]:
                raise ManifestError(f"{where(line, c)}: empty")
        for c in ("take", "actor"):
            if not ID.match(cell[c]):
                raise ManifestError(f"{where(line, c)}: '{cell[c]}' is not an id (letters, "
                                    "digits, '.', '_', '-')")
        if cell["take"] in takes:
            raise ManifestError(f"{where(line, 'take')}: '{cell['take']}' already on line "
                                f"{takes[cell['take']].line}")
        try:
            options = shlex.split(cell.get("options", ""))
        except ValueError as e:
            raise ManifestError(f"{where(line, 'options')}: {e}") from None
        seconds = 0.0
        if cell.get("seconds"):
            try:
                seconds = float(cell["seconds"])
            except ValueError:
                seconds = -1.0
            if not 0 < seconds <= 86400:
                raise ManifestError(f"{where(line, 'seconds')}: '{cell['seconds']}' is not a "
                                    "length in seconds (0, 86400]")
        layout = cell["layout"]
        take = Take(take=cell["take"], actor=cell["actor"], source=resolve(cell["source"]),
                    layout=layout if layout == "markerless" else resolve(layout),
                    camera=resolve(cell["camera"]) if cell.get("camera") else "",
                    neutral=resolve(cell["neutral"]), options=options, seconds=seconds,
                    line=line)
        for c, p in (("layout", take.layout), ("camera", take.camera),
                     ("neutral", take.neutral)):
            if p and p != "markerless" and not os.path.exists(p):
                raise ManifestError(f"{where(line, c)}: {p} does not exist")
        takes[take.take] = take
    if not takes:
        raise ManifestError(f"{path}: no takes (only a header)")
    return takes


def actors(takes, path="manifest"):
    """Each actor once, as a dict name -> Actor; rows of one actor must agree."""
    found = {}
    for t in takes.values():
        a = Actor(t.actor, t.layout, t.camera, t.neutral, t.line)
        if t.actor not in found:
            found[t.actor] = a
            continue
        first = found[t.actor]
        for c in ("layout", "camera", "neutral"):
            if getattr(first, c) != getattr(a, c):
                raise ManifestError(
                    f"{path}: line {t.line}, column '{c}': actor '{t.actor}' has "
                    f"'{getattr(a, c) or '(empty)'}' here but '{getattr(first, c) or '(empty)'}' "
                    f"on line {first.line}; an actor is calibrated once, so every row of an "
                    "actor gives the same layout, camera and neutral")
    return found
