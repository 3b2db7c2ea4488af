"""What a browser sends viser first: its camera. viser counts a client as connected only once it has."""

from __future__ import annotations

import msgspec

CAMERA_HELLO = msgspec.msgpack.encode(
    {
        "type": "ViewerCameraMessage",
        "wxyz": (1.0, 0.0, 0.0, 0.0),
        "position": (1.1, -1.3, 0.9),
        "fov": 1.0,
        "near": 0.01,
        "far": 100.0,
        "image_height": 900,
        "image_width": 1400,
        "look_at": (0.0, 0.0, 0.35),
        "up_direction": (0.0, 0.0, 1.0),
    }
)
