"""The result store of a screening: one small JSON file per finished compound.

``<out>/compounds/<key>.json`` holds one compound's record (:func:`tire_brush.screening.
evaluate.evaluate_compound`); the key is a SHA-256 over what the record depends on: the
compound description, the bytes of every file it reads, and the screening settings (grids'
axes and engine settings, tire, test and study specs' paths and their bytes, the package
version). A rerun of the same screen finds the finished compounds and skips them; an
interrupted run resumes with the rest; a changed compound, file or setting gets a new key and
is computed again. Files are written atomically (temporary file, then rename), so a killed
run leaves finished records or none, never half of one.
"""

from __future__ import annotations

import hashlib
import json
import os
from pathlib import Path
from typing import Any

from .compounds import file_digest, referenced_files


def compound_key(desc: dict[str, Any], settings_description: dict[str, Any],
                 kind: str = "compound") -> str:
    """SHA-256 (hex) of a compound description with the digests of the files it reads and
    the screening settings (module docstring)."""
    files = {f: file_digest(f) for f in referenced_files(desc)}
    s = settings_description
    setting_files = {k: file_digest(s[k]) for k in ("tire", "wet_grip_spec", "study")
                     if k in s}
    blob = json.dumps({"kind": kind, "compound": desc, "files": files, "settings": s,
                       "setting_files": setting_files}, sort_keys=True, default=str)
    return hashlib.sha256(blob.encode()).hexdigest()


class ResultStore:
    """Records of finished compounds under ``<out>/compounds``."""

    def __init__(self, out: str | Path) -> None:
        self.folder = Path(out) / "compounds"
        self.folder.mkdir(parents=True, exist_ok=True)

    def path(self, key: str) -> Path:
        """The record file of a key."""
        return self.folder / f"{key}.json"

    def get(self, key: str) -> dict[str, Any] | None:
        """The finished record of ``key`` (status ``ok``), or None: failed compounds are
        tried again (their cause may have been fixed), unreadable files ignored."""
        p = self.path(key)
        if not p.is_file():
            return None
        try:
            rec = json.loads(p.read_text(encoding="utf-8"))
        except (OSError, ValueError):
            return None
        return rec if rec.get("status") == "ok" and rec.get("key") == key else None

    def put(self, record: dict[str, Any]) -> Path:
        """Write a record atomically."""
        p = self.path(record["key"])
        tmp = p.with_name(f".{p.name}.tmp-{os.getpid()}")
        tmp.write_text(json.dumps(record, indent=1, sort_keys=True, allow_nan=True),
                       encoding="utf-8")
        os.replace(tmp, p)
        return p
