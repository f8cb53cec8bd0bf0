"""tirefric ``tire_brush``: a brush tire on Persson friction grids.

Steady state (:class:`~tire_brush.steady.SteadyBrush`) and transient
(:class:`~tire_brush.transient.TransientBrushTire`) brush models share one tread-element law
(:mod:`tire_brush.element`): stick, or slide with the cold/hot blending of review eq. (28)
(:mod:`tire_brush.friction`), a tip mass and damping that keep velocity-weakening friction well
posed. Tire data come from TOML files (:mod:`tire_brush.params`, shipped ``passenger``);
Pacejka's closed-form brush is package code (:mod:`tire_brush.reference`). Braking studies
live in :mod:`tire_brush.braking`.

Importing this package imports nothing heavy: the transient model, the friction adapters and
the parameters need numpy and the standard library only (they run inside an FMU).
"""

