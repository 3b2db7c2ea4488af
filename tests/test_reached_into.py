"""What the pendant uses of uvicorn's and viser's private parts is still there, in the shape it expects.

Both are pinned in pyproject.toml for this reason; a new version that moves one of these pieces fails here,
by name, rather than somewhere deep in a connection test or (worse) only in a user's fresh install.
"""

from __future__ import annotations

import asyncio
import inspect
import tomllib
from collections.abc import Callable, Iterator
from importlib.metadata import version
from pathlib import Path
from typing import Any

import msgspec
import numpy as np
import pytest
import uvicorn
import viser
import viser._assignable_props_api
import viser._gui_api
import viser._gui_handles
import viser._icons
import zstandard
from uvicorn.protocols.http.httptools_impl import HttpToolsProtocol
from uvicorn.server import ServerState
from viser import _messages
from viser.infra import ClientId

from pendant.api.quitting import QuitAwareServer
from pendant.api.serving import GuardedHttpProtocol
from pendant.ui.kit import viser_broadcast
from pendant.ui.page.ws_guard import ProcessRequest, guarded_viser_server
from tests.support.ports import free_port

PYPROJECT = Path(__file__).parents[1] / "pyproject.toml"


def parameters(function: Callable[..., Any]) -> list[str]:
    return list(inspect.signature(function).parameters)


def pinned(name: str) -> str:
    """The version pyproject.toml pins `name` to ("name==X" or "name[extra]==X")."""
    dependencies = tomllib.loads(PYPROJECT.read_text())["project"]["dependencies"]
    (pin,) = (d for d in dependencies if d.split("[")[0].split("=")[0] == name)
    assert "==" in pin, f"{name} must be pinned (the pendant reaches into its private parts): {pin}"
    return pin.split("==")[1]


@pytest.mark.parametrize("name", ["uvicorn", "viser"])
def test_the_installed_version_is_the_pinned_one(name: str) -> None:
    assert version(name) == pinned(name), (
        f"{name} {version(name)} installed, {pinned(name)} pinned and checked"
    )


# --- uvicorn: pendant/api/serving.py and pendant/api/quitting.py -----------------------------------------


def test_the_httptools_protocol_has_the_hooks_the_guarded_protocol_overrides() -> None:
    expected = {
        "connection_made": ["self", "transport"],
        "connection_lost": ["self", "exc"],
        "data_received": ["self", "data"],
        "on_headers_complete": ["self"],
        "on_message_complete": ["self"],
        "on_response_complete": ["self"],
    }
    for name, params in expected.items():
        assert parameters(getattr(HttpToolsProtocol, name)) == params, f"HttpToolsProtocol.{name}"
        assert getattr(GuardedHttpProtocol, name) is not getattr(HttpToolsProtocol, name), name


class StillTransport(asyncio.Transport):
    """A connection that sends nothing: what connection_made and connection_lost are given."""

    def __init__(self) -> None:
        super().__init__()
        self.closed = False

    def get_extra_info(self, name: str, default: Any = None) -> Any:
        return default

    def is_closing(self) -> bool:
        return self.closed

    def close(self) -> None:
        self.closed = True


def test_a_protocol_instance_has_the_state_the_guarded_protocol_reads() -> None:
    loop = asyncio.new_event_loop()
    try:
        config = uvicorn.Config(app=lambda scope, receive, send: None, log_level="warning")
        state = ServerState()
        protocol = GuardedHttpProtocol(config, state, {}, _loop=loop)
        assert protocol.loop is loop and len(protocol.pipeline) == 0
        transport = StillTransport()
        protocol.connection_made(transport)
        assert protocol.transport is transport and protocol.connections is state.connections
        assert protocol in state.connections and protocol in protocol.waiting
        protocol.connection_lost(None)
        assert protocol not in state.connections and protocol not in protocol.waiting
    finally:
        loop.close()


def test_the_server_has_the_exit_hooks_the_quit_aware_server_overrides() -> None:
    assert parameters(uvicorn.Server.handle_exit) == ["self", "sig", "frame"]
    assert parameters(uvicorn.Server.shutdown) == ["self", "sockets"]
    assert inspect.iscoroutinefunction(uvicorn.Server.shutdown)
    assert QuitAwareServer.handle_exit is not uvicorn.Server.handle_exit


# --- viser: pendant/ui ------------------------------------------------------------------------------------


@pytest.fixture
def server() -> Iterator[viser.ViserServer]:
    server = viser.ViserServer(host="127.0.0.1", port=free_port(), verbose=False)
    yield server
    server.stop()


def test_the_websocket_server_is_built_through_websockets_serve_with_a_process_request() -> None:
    """pendant/ui/page/ws_guard.py: the origin guard is put in front of viser's own process_request."""
    wrapped: list[ProcessRequest | None] = []

    def wrap(inner: ProcessRequest | None) -> ProcessRequest:
        wrapped.append(inner)
        assert inner is not None
        return inner

    with guarded_viser_server(None, wrap):
        built = viser.ViserServer(host="127.0.0.1", port=free_port(), verbose=False)
    built.stop()
    assert len(wrapped) == 1 and wrapped[0] is not None, "viser no longer serves through websockets' serve()"


def test_the_live_connections_are_kept_by_client_id(server: viser.ViserServer) -> None:
    """pendant/ui/page/browsers.py reads the handshake of a browser's websocket there."""
    assert isinstance(server._websock_server._live_connections, dict)


def test_the_upload_handlers_and_states_are_where_the_upload_limit_wraps_them(
    server: viser.ViserServer,
) -> None:
    """pendant/ui/kit/upload_limit.py, with the state keys it reads; tests/support/doubles.upload_states."""
    gui = server.gui
    handlers = gui._websock_interface._incoming_handlers
    assert gui._handle_file_transfer_start in handlers[_messages.FileTransferStartUpload]
    assert gui._handle_file_transfer_part in handlers[_messages.FileTransferPart]
    assert gui._owner is server
    button = gui.add_upload_button("Upload")
    start = _messages.FileTransferStartUpload(
        source_component_uuid=button._impl.uuid,
        transfer_uuid="t1",
        filename="f.json",
        mime_type="application/json",
        part_count=2,
        size_bytes=10,
    )
    gui._handle_file_transfer_start(ClientId(0), start)
    state = gui._current_file_upload_states["t1"]
    assert state["total_bytes"] == 10 and state["transferred_bytes"] == 0
    part = _messages.FileTransferPart(
        source_component_uuid=button._impl.uuid, transfer_uuid="t1", part_index=0, content=b"x"
    )
    assert (part.transfer_uuid, part.content) == ("t1", b"x")


def test_a_handles_state_has_the_fields_the_page_and_the_test_kit_use(server: viser.ViserServer) -> None:
    """view_only.py and the jog panel key controls by `_impl.uuid`; the kit's fire/confirm_hold/drag call
    viser's callbacks as a browser's message would."""
    button = server.gui.add_button("Hold")
    button.on_hold(lambda _: None, callback_hz=10.0)
    assert isinstance(button._impl.uuid, str) and isinstance(button._impl.update_cb, list)
    assert len(button._button_impl.hold_cbs_from_freq[10.0]) == 1
    number = server.gui.add_number("n", initial_value=1.0)
    number._impl.value = 2.0
    assert number.value == 2.0
    gizmo = server.scene.add_transform_controls("/gizmo")
    assert isinstance(gizmo._impl_aux.update_cb, list)
    gizmo._impl.position = np.array([0.1, 0.2, 0.3])
    assert tuple(gizmo.position) == pytest.approx((0.1, 0.2, 0.3))


def test_the_icon_and_type_hint_lookups_the_page_caches_are_there() -> None:
    """pendant/ui/kit/viser_caches.py: without them the page still works, only slower (so check loudly)."""
    assert (viser._icons.ICONS_DIR / "tabler-icons.zip").is_file()
    for module in (viser._icons, viser._gui_api, viser._gui_handles):
        assert callable(getattr(module, "svg_from_icon", None)), f"{module.__name__}.svg_from_icon"
    assert "_prop_hints" in vars(viser._assignable_props_api.AssignablePropsBase)


def test_the_broadcast_producer_the_page_replaces_has_its_shape() -> None:
    """pendant/ui/kit/viser_broadcast.py: viser's per-browser producer, called by name from its handler."""
    assert viser_broadcast.viser_has_the_expected_shape(), (
        "viser's _message_producer changed: broadcasts would be serialised per browser again"
    )


def test_a_broadcast_frame_carries_what_viser_would_send() -> None:
    """The frame made once for all browsers decodes to the messages viser's own serialisation gives."""
    outgoing = [
        _messages.SetPositionMessage("/a", (0.1, 0.2, 0.3)),
        _messages.SetOrientationMessage("/a", (1.0, 0.0, 0.0, 0.0)),
        _messages.SetPositionMessage("/b", (0.4, 0.5, 0.6)),
    ]
    frame = viser_broadcast.broadcast_frame(outgoing)
    again = viser_broadcast.broadcast_frame(outgoing)
    inner_size = int.from_bytes(frame[:8], "little")
    compressed = int.from_bytes(frame[8:16], "little")
    inner = zstandard.ZstdDecompressor().decompress(frame[16 : 16 + compressed], max_output_size=inner_size)
    decoded = msgspec.msgpack.decode(inner)
    expected = msgspec.msgpack.decode(msgspec.msgpack.encode([m.as_serializable_dict([]) for m in outgoing]))
    assert decoded["messages"] == expected
    assert decoded["binaryBufferLengths"] == []
    assert again is frame  # the same window for the next browser: not made again
