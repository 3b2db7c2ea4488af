"""One frozen record of the pendant's settings, built by the CLI."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal, get_args

# viser's HDR environment maps (SceneApi.configure_environment_map's `hdri`), for --environment-map; a test
# checks this list against viser's.
EnvironmentMap = Literal[
    "apartment", "city", "dawn", "forest", "lobby", "night", "park", "studio", "sunset", "warehouse"
]
ENVIRONMENT_MAPS: tuple[EnvironmentMap, ...] = get_args(EnvironmentMap)


@dataclass(frozen=True)
class Settings:
    host: str = "127.0.0.1"
    ui_port: int = 8080
    api_port: int = 8081
    model: str = "pulse75"
    robot_url: str | None = None  # None: the embedded simulator
    no_ui: bool = False
    token: str | None = None
    programs_dir: str | None = None  # None: $PENDANT_PROGRAMS_DIR, else ./programs
    data_dir: str | None = None  # the event log and recordings; None: $PENDANT_DATA_DIR, else beside programs
    # The link to a real controller (--robot), in seconds: the client's and the proxy's. Short, so a dead
    # controller is reported within a read timeout rather than hanging the page or a script.
    connect_timeout: float = 1.0
    read_timeout: float = 3.0
    # Commands through the proxy (anything but GET/HEAD/OPTIONS) wait this long for the controller's answer:
    # under load a late answer is far better than a 504 that leaves the client in doubt.
    command_timeout: float = 30.0
    remote_control: bool | None = None  # --remote-control on|off; None: on only for the simulator on loopback
    allowed_hosts: tuple[str, ...] = ()  # --allowed-host: names the pendant answers to besides IPs, localhost
    # Simulated time per wall-clock second (the simulator's clock; --time-scale, not with --robot).
    time_scale: float = 1.0
    # --foxglove-port: the Foxglove live view (the Foxglove WebSocket protocol) on --host; None: off.
    foxglove_port: int | None = None
    fresh_cell: bool = False  # --fresh-cell: the simulator starts with no obstacle, default tool and base
    # --environment-map: one of ENVIRONMENT_MAPS lights the 3D view; None: lights alone.
    environment_map: EnvironmentMap | None = None
