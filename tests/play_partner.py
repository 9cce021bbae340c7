"""A partner policy for ``legent-gym play --partner tests.play_partner:announcer`` (the
``module:function`` form): it says the instruction it was reset with, then turns 45 degrees
every step."""

from __future__ import annotations

TURN = 45


class Announcer:
    def __init__(self) -> None:
        self.instruction: str | None = None
        self.said = False

    def reset(self, instruction: str) -> None:
        self.instruction, self.said = instruction, False

    def act(self, observation: dict) -> str:
        if not self.said:
            self.said = True
            return f'speak("heard: {self.instruction}")'
        return f"rotate_right({TURN})"


def announcer() -> Announcer:
    return Announcer()
