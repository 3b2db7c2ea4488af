"""What the simulated arm says about itself: model, serial numbers, firmware versions (stable per model)."""

from __future__ import annotations

import hashlib

from pendant.controller.system_types import RobotInfo, Version

ROBOT_SOFTWARE_VERSION = "1.8.2"  # the API version SDK 1.8.4 was generated from
_MODEL_NAMES = {"pulse75": "PULSE75", "pulse90": "PULSE90"}
_MODEL_REVISIONS = {"pulse75": "2.1", "pulse90": "2.1"}


def _serial(model: str, part: str) -> str:
    digest = hashlib.sha256(f"pulse-serial:{model}:{part}".encode()).hexdigest()
    return f"{part[:2].upper()}{int(digest[:10], 16) % 10**8:08d}"


def robot_info(model: str) -> RobotInfo:
    return RobotInfo(
        model=_MODEL_NAMES.get(model, "Unknown"),
        version=_MODEL_REVISIONS.get(model, "Unknown"),
        controlBoxSerialNumber=_serial(model, "control-box"),
        armSerialNumber=_serial(model, "arm"),
    )


def hardware_version(model: str) -> Version:
    motors = ["3.2"] * 3 + ["3.1"] * 3  # the two servo sizes (J1-J3, J4-J6)
    return Version(motorsVersion=motors, safetyVersion="1.4", usbCanVersion="2.0", wristVersion="1.2")


def software_version(model: str) -> Version:
    motors = ["2.9.14"] * 6
    return Version(motorsVersion=motors, safetyVersion="1.7.3", usbCanVersion="1.3.0", wristVersion="1.5.1")
