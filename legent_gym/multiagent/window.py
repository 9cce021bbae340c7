"""A window for ``render_mode="human"``: the frames a PettingZoo env renders, shown with pygame.

On a machine without a display (neither ``DISPLAY`` nor ``WAYLAND_DISPLAY`` set, and no
``SDL_VIDEODRIVER`` chosen) the window opens on SDL's ``dummy`` video driver, with a
warning: everything runs and nothing is shown (so ``pettingzoo.test.render_test`` passes
on a headless machine). With a display the frames are paced at the env's ``render_fps``.
"""

from __future__ import annotations

import os
import time
import warnings

import numpy as np


def _pygame():
    os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")
    try:
        # pygame: optional, for render_mode='human' alone
        import pygame
    except ImportError as err:
        raise ImportError("render_mode='human' needs pygame: pip install 'legent-gym[multiagent]'") from err
    return pygame


class Window:
    """Shows RGB frames in pygame's window (one per process: envs in human mode share it),
    opened at the first frame."""

    def __init__(self, title: str, fps: float):
        self.pygame = _pygame()  # fails at construction, not at the first frame, without pygame
        self.title, self.fps = title, float(fps)
        self._opened = False
        self._shown_at = 0.0

    def show(self, frame: np.ndarray) -> None:
        pygame = self.pygame
        height, width = frame.shape[:2]
        if not pygame.display.get_init():
            _choose_driver()
            pygame.display.init()
        screen = pygame.display.get_surface()
        if screen is None or screen.get_size() != (width, height):
            screen = pygame.display.set_mode((width, height))
        self._opened = True
        pygame.display.set_caption(self.title)
        pygame.event.pump()  # keeps the window responsive
        screen.blit(pygame.surfarray.make_surface(np.ascontiguousarray(frame.swapaxes(0, 1))), (0, 0))
        pygame.display.flip()
        if pygame.display.get_driver() not in ("dummy", "offscreen") and self.fps > 0:
            wait = self._shown_at + 1.0 / self.fps - time.monotonic()
            if wait > 0:
                time.sleep(wait)
        self._shown_at = time.monotonic()

    def close(self) -> None:
        if self._opened:
            self.pygame.display.quit()
        self._opened = False


def _choose_driver() -> None:
    """SDL's dummy video driver where there is no display and none was chosen."""
    if os.environ.get("SDL_VIDEODRIVER") or os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"):
        return
    warnings.warn("render_mode='human' without a display (no DISPLAY or WAYLAND_DISPLAY): the window opens on "
                  "SDL's dummy video driver and shows nothing; render_mode='rgb_array' returns the frames",
                  stacklevel=4)
    os.environ["SDL_VIDEODRIVER"] = "dummy"
