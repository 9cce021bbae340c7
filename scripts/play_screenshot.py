"""Take the README's picture of the play page: ``legent-gym play`` started as a user starts
it, the page opened in a headless Chromium (Debian's ``chromium``, driven by Playwright),
the user turned to the agent and the instruction said, the
expert agent come; the page is saved as a PNG.

    .venv/bin/python scripts/play_screenshot.py [--out docs/images/play.png] [--env Legent/ComeHere-TwoRoom-v0]
"""

from __future__ import annotations

import argparse
import math
import re
import shutil
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
CHROMIUM_ARGS = ["--no-sandbox", "--headless", "--disable-gpu", "--no-first-run", "--disable-background-networking",
                 "--disable-component-update", "--disable-sync"]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", default=str(ROOT / "docs" / "images" / "play.png"))
    parser.add_argument("--env", default="Legent/ComeHere-TwoRoom-v0")
    parser.add_argument("--seed", default="5")
    parser.add_argument("--size", default="640x480")
    parser.add_argument("--chromium", default=shutil.which("chromium") or "/usr/bin/chromium")
    args = parser.parse_args()
    from playwright.sync_api import sync_playwright

    cmd = [sys.executable, "-m", "legent_gym.cli", "play", args.env, "--port", "0", "--size", args.size,
           "--seed", args.seed, "--tick", "1.0"]
    server = subprocess.Popen(cmd, cwd=ROOT, stdout=subprocess.PIPE, text=True)
    try:
        assert server.stdout is not None
        match = re.search(r"http://\S+", server.stdout.readline())
        if match is None:
            raise SystemExit("the server printed no URL")
        with sync_playwright() as p:
            browser = p.chromium.launch(executable_path=args.chromium, args=CHROMIUM_ARGS)
            page = browser.new_context(bypass_csp=True, viewport={"width": 1200, "height": 860}).new_page()
            page.goto(match.group(0))
            page.wait_for_function("window.play && window.play.frames > 2 && window.play.map", timeout=60_000)
            state = page.evaluate("window.play.state")  # turn (30 degrees a key) to face the agent
            (ux, uy, yaw, _), (ax, ay) = state["user_pose"], state["agent_pose"][:2]
            turns = round(((yaw - math.degrees(math.atan2(ay - uy, ax - ux))) % 360) / 30) % 12
            for key in ["d"] * turns if turns <= 6 else ["a"] * (12 - turns):
                used = page.evaluate("window.play.state.actions_used")
                page.keyboard.press(key)
                page.wait_for_function(f"window.play.state.actions_used > {used}", timeout=20_000)
            page.click("#show-instruction")
            page.keyboard.press("Enter")
            page.keyboard.type(page.evaluate("window.play.state.instruction"))
            page.keyboard.press("Enter")
            used = page.evaluate("window.play.state.actions_used")
            page.wait_for_function("window.play.state.done", timeout=60_000)
            page.wait_for_timeout(1500)  # an fps figure on the status line
            Path(args.out).parent.mkdir(parents=True, exist_ok=True)
            page.screenshot(path=args.out)
            browser.close()
        print(f"wrote {args.out}")
    finally:
        server.terminate()
        server.wait(timeout=10)
    return 0


if __name__ == "__main__":
    sys.exit(main())
