"""An episode as an H.264 mp4 with the action as a caption, and its top-down map.

Frame n of the video is the view before action n with that action written under it; the
last frame is the final view, captioned with the outcome, so a video has ``steps + 1``
frames. An env with ``frames_per_step`` F > 1 adds the F - 1 views within each step after
its first frame (the same caption), and the video plays F times as many frames a second,
so that an episode lasts as long and people walk instead of jumping. Views are scaled up
(nearest neighbour) so that the caption is legible.
H.264 comes from PyAV (``av``, extra ``data``): OpenCV's writers cannot encode it here.
"""

from __future__ import annotations

import io
import textwrap

import cv2
import numpy as np

from legent_gym.data.rollout import Episode
from legent_gym.world.topdown_map import draw_topdown_map

FPS = 2
MIN_VIEW_WIDTH = 320
CAPTION_LINES = 3
LINE_HEIGHT = 18
FONT = cv2.FONT_HERSHEY_SIMPLEX
FONT_SCALE = 0.45


def _even(n: int) -> int:
    return n + (n % 2)  # yuv420p needs even sizes


def _caption(width: int, lines: list[str]) -> np.ndarray:
    bar = np.full((CAPTION_LINES * LINE_HEIGHT + 8, width, 3), 20, dtype=np.uint8)
    for i, line in enumerate(lines[:CAPTION_LINES]):
        text = line.encode("ascii", "replace").decode()  # Hershey fonts draw ASCII only
        cv2.putText(bar, text, (6, 4 + (i + 1) * LINE_HEIGHT - 4), FONT, FONT_SCALE, (235, 235, 235), 1, cv2.LINE_AA)
    return bar


def caption_lines(episode: Episode, n: int, width: int) -> list[str]:
    chars = max(10, width // 9)
    head = textwrap.shorten(episode.instruction, chars, placeholder="...")
    if n < episode.steps:
        body = f"{n}: {episode.action_texts[n]}"
    else:
        body = f"end after {episode.steps} actions: {'success' if episode.success else 'failure'}"
    return [head, *textwrap.wrap(body, chars)[:CAPTION_LINES - 1]]


def video_frames(episode: Episode) -> list[np.ndarray]:
    """The captioned RGB frames (``steps + 1`` of them, and the views within steps)."""
    h, w = episode.observations[0]["rgb"].shape[:2]
    scale = max(1, -(-MIN_VIEW_WIDTH // w))
    frames = []
    for n, obs in enumerate(episode.observations):
        within = episode.between[n] if n < len(episode.between) else []
        caption = _caption(w * scale, caption_lines(episode, n, w * scale))
        for image in (obs["rgb"], *within):
            view = np.repeat(np.repeat(image, scale, axis=0), scale, axis=1)
            frame = np.vstack([view, caption])
            pad_h, pad_w = _even(frame.shape[0]) - frame.shape[0], _even(frame.shape[1]) - frame.shape[1]
            frames.append(np.pad(frame, ((0, pad_h), (0, pad_w), (0, 0))))
    return frames


def frames_per_step(episode: Episode) -> int:
    """F of the env that recorded ``episode`` (1 + the views within its first step)."""
    return 1 + (len(episode.between[0]) if episode.between else 0)


def encode_mp4(frames: list[np.ndarray], fps: int = FPS) -> bytes:
    """H.264 (yuv420p, browser-playable) mp4 bytes of RGB frames of one size."""
    # av (H.264): the data extra
    import av

    if not frames:
        raise ValueError("a video needs at least one frame")
    h, w = frames[0].shape[:2]
    buffer = io.BytesIO()
    with av.open(buffer, mode="w", format="mp4") as container:
        # veryfast: a few ms for a short episode, about the size of the default preset here.
        stream = container.add_stream("libx264", rate=fps, options={"preset": "veryfast"})
        stream.width, stream.height, stream.pix_fmt = w, h, "yuv420p"
        for frame in frames:
            for packet in stream.encode(av.VideoFrame.from_ndarray(frame, format="rgb24")):
                container.mux(packet)
        for packet in stream.encode():
            container.mux(packet)
    return buffer.getvalue()


def episode_video(episode: Episode, fps: int = FPS) -> bytes:
    """The episode's mp4 at ``fps`` steps a second (``fps`` x F frames a second)."""
    return encode_mp4(video_frames(episode), fps * frames_per_step(episode))


def read_video(data_or_path) -> list[np.ndarray]:
    """Decode an mp4 (a path or bytes) to RGB frames."""
    # av (H.264): the data extra
    import av

    source = io.BytesIO(data_or_path) if isinstance(data_or_path, bytes | bytearray) else str(data_or_path)
    with av.open(source, mode="r") as container:
        return [frame.to_ndarray(format="rgb24") for frame in container.decode(video=0)]


def episode_map(scene, episode: Episode, size: int = 480) -> np.ndarray:
    """The house seen from above with the agent's path drawn, and both people where the
    episode ended."""
    last = episode.infos[-1] if episode.infos else None
    people = None
    if last is not None:
        people = {"agent": tuple(last["agent_pose"][:3])}
        if not np.isnan(last["user_pose"][0]):
            people["user"] = tuple(last["user_pose"][:3])
    return draw_topdown_map(scene, size=size, path=episode.path, people=people)
