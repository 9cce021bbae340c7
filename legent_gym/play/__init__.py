"""Play in the browser: ``legent-gym play ENV_ID`` (needs the ``play`` extra).

A person plays the user (the partner policy drives the agent) or the agent (and may
record the episodes as a dataset) in a page served by the simulator process:

* :mod:`~legent_gym.play.session`: :class:`PlaySession`, the env a person plays, the
  partner policies, the person's view and the map;
* :mod:`~legent_gym.play.recorder`: episodes played as the agent, written in the LEGENT and
  Minari formats as ``legent-gym collect`` writes them;
* :mod:`~legent_gym.play.server`: the HTTP page and the WebSocket (JPEG frames, JSON state);
* :mod:`~legent_gym.play.command`: the command's arguments;
* ``static/``: the page (``index.html``, ``play.js``, ``play.css``; no build step).

See ``docs/play.md``.
"""
