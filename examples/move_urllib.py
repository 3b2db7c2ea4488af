"""Move the arm with nothing but Python's standard library: PUT /pose, wait, read the pose back.

Usage: python examples/move_urllib.py [URL]   (default: $PULSE_URL, else http://127.0.0.1:8081)
"""

from __future__ import annotations

import json
import os
import sys
import time
import urllib.request
from typing import Any

TARGET = [-30.0, -80.0, 80.0, -90.0, -90.0, 15.0]  # degrees, J1..J6


def call(method: str, url: str, body: object = None) -> Any:  # JSON: whatever the path answers
    data = None if body is None else json.dumps(body).encode()
    headers = {"Content-Type": "application/json"}
    request = urllib.request.Request(url, data=data, method=method, headers=headers)
    with urllib.request.urlopen(request, timeout=10) as response:
        text = response.read().decode()
    return json.loads(text) if text else None


def main() -> None:
    url = sys.argv[1] if len(sys.argv) > 1 else os.environ.get("PULSE_URL", "http://127.0.0.1:8081")
    call("PUT", f"{url}/pose?speed=40", {"angles": TARGET})
    while call("GET", f"{url}/status/motion") == "RUNNING":
        time.sleep(0.05)
    angles = call("GET", f"{url}/pose")["angles"]
    print("arrived at", " ".join(f"{a:.2f}" for a in angles))


if __name__ == "__main__":
    main()
