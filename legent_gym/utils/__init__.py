"""What the layers share and none owns: :mod:`~legent_gym.utils.gl_backend` (picks EGL
before MuJoCo is imported), :mod:`~legent_gym.utils.atomic` (atomic file writes),
:mod:`~legent_gym.utils.heap` (the C heap's freed pages handed back),
:mod:`~legent_gym.utils.workers` (worker processes: forkserver, one core each) and
:mod:`~legent_gym.utils.scale` (the same loops as Ray tasks). Import the module you need;
this package imports none of them."""
