"""tirefric ``lookup``: Persson rubber-friction theory and the friction grids built from it.

Data flow (see ``docs/design.md``): compound and surface files (``models/``) ->
:mod:`lookup.compound`, :mod:`lookup.surface` -> :class:`lookup.friction.PerssonFriction`
(cold and hot branch) -> grids. This package knows nothing of tires.
"""
