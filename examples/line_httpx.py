"""Move the tool 5 cm up in a straight line with httpx: read the TCP, PUT /position (LINEAR), wait, print.

Usage: python examples/line_httpx.py [URL]   (default: $PULSE_URL, else http://127.0.0.1:8081)
"""

from __future__ import annotations

import os
import sys
import time

import httpx

RISE_M = 0.05


def main() -> None:
    url = sys.argv[1] if len(sys.argv) > 1 else os.environ.get("PULSE_URL", "http://127.0.0.1:8081")
    with httpx.Client(base_url=url, timeout=10.0) as api:
        # {"point": {"x", "y", "z"} in metres, "rotation": {"roll", "pitch", "yaw"} in radians}
        start = api.get("/position").json()
        target = {**start, "point": {**start["point"], "z": start["point"]["z"] + RISE_M}}
        api.put("/position", params={"speed": 30, "motionType": "LINEAR"}, json=target).raise_for_status()
        while api.get("/status/motion").json() == "RUNNING":
            time.sleep(0.05)
        end = api.get("/position").json()["point"]
    print(f"tcp z: {start['point']['z']:.4f} -> {end['z']:.4f} m")


if __name__ == "__main__":
    main()
