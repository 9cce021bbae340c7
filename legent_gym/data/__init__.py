"""Recording and exporting trajectories: Minari datasets, LEGENT's format with an
image-text interleaved JSONL for VLA training, and captioned H.264 videos.

* :mod:`~legent_gym.data.rollout`: run one episode with a policy ``(obs, info) -> action``
  (by default the expert, ``info["expert_action"]``) and keep what the exports need;
* :mod:`~legent_gym.data.minari_store`: crash-safe, appendable Minari datasets;
* :mod:`~legent_gym.data.legent_format`: ``NNNN.png`` + ``trajectory.json`` per trajectory,
  the aggregated list and ``interleaved.jsonl``;
* :mod:`~legent_gym.data.video`: the mp4 with the actions as captions and the top-down path;
* :mod:`~legent_gym.data.collect`: ``legent-gym collect`` (parallel, resumable).

See ``docs/datasets.md``.
"""

from legent_gym.data.collect import CollectConfig, CollectError, CollectSummary, collect
from legent_gym.data.rollout import Episode, expert_policy, record_episode

__all__ = ["CollectConfig", "CollectError", "CollectSummary", "Episode", "collect", "expert_policy",
           "record_episode"]
