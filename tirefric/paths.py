"""Where the shipped data (``models/``) lives, and how shipped names resolve to files.

The ``models/`` folder of the repository is installed as the data package ``tirefric_models``
(see ``pyproject.toml``), so that a non-editable ``pip install`` finds it as well as a source
checkout does.
"""

from __future__ import annotations

from pathlib import Path

from .errors import InputError


def models_dir() -> Path:
    """Return the folder holding the shipped compounds, surfaces, tires, grids and studies."""
    try:
        import tirefric_models  # installed data package (the repository's models/ folder)

        path = Path(next(iter(tirefric_models.__path__)))
        if path.is_dir():
            return path
    except ImportError:
        pass
    here = Path(__file__).resolve().parent.parent / "models"
    if here.is_dir():
        return here
    raise FileNotFoundError("cannot locate the shipped models/ data folder")


def resolve_model_file(name_or_path: str | Path, kind: str, suffix: str = ".toml") -> Path:
    """Resolve a shipped model name (``"summer"``) or a path to an existing file.

    Parameters
    ----------
    name_or_path
        A path to a file, or the name of a shipped model of this kind.
    kind
        Sub-folder of ``models/``: ``"compounds"``, ``"surfaces"``, ``"tires"``, ``"grids"``,
        ``"studies"``.
    suffix
        File suffix of shipped models of this kind.
    """
    p = Path(name_or_path)
    if p.is_file():
        return p
    shipped = models_dir() / kind / f"{name_or_path}{suffix}"
    if shipped.is_file():
        return shipped
    available = sorted(f.stem for f in (models_dir() / kind).glob(f"*{suffix}"))
    raise InputError(
        f"no such file, and not a shipped {kind[:-1]} name (shipped: {', '.join(available)})",
        source=str(name_or_path),
    )
