"""tirefric's base: errors, units, model-file reading, the shipped data's paths, the CLI root.

Everything else builds on it (docs/design.md, "Dependency direction"): the friction engine
``lookup``, the brush tire ``tire_brush`` and the FMUs ``fmu_src`` import from here, never the
reverse. It holds no physics.
"""

__version__ = "0.1.0"
