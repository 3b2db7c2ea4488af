"""/openapi.json and /docs describe the PULSE API as the reference does, and the simulator's extras apart."""

from __future__ import annotations

import importlib
import importlib.metadata
import inspect
import json
import pkgutil
import re
from typing import Any

import pytest
from fastapi.testclient import TestClient

from pendant.api import create_app
from pendant.api.docs import TAG_SIM
from pendant.controller.errors import MSG_BAD_FORMAT, MSG_EMERGENCY, MSG_NOT_RESPONDING
from tests.support.api_client import RecordingController

PULSE_OPERATIONS = {
    ("get", "/position"),
    ("get", "/status/motion"),
    ("get", "/status/motors"),
    ("get", "/pose"),
    ("get", "/tool"),
    ("get", "/base"),
    ("get", "/robot/id"),
    ("get", "/signal/output/{port}"),
    ("get", "/signal/input/{port}"),
    ("put", "/position"),
    ("put", "/pose"),
    ("put", "/gripper/open"),
    ("put", "/gripper/close"),
    ("put", "/relax"),
    ("put", "/freeze"),
    ("put", "/poses/run"),
    ("put", "/positions/run"),
    ("put", "/signal/output/{port}/high"),
    ("put", "/signal/output/{port}/low"),
    ("put", "/recover"),
    ("put", "/pack"),
    ("post", "/tool"),
    ("post", "/base"),
}
# What Rozum's SDK 1.8.4 adds (reference/pulse-api-1.8.md): 30 operations; the SDK sends 51 in all.
SDK_OPERATIONS = {
    ("get", "/status"),
    ("get", "/status/failure"),
    ("get", "/robot/info"),
    ("get", "/tool/info"),
    ("post", "/tool/info"),
    ("get", "/tool/shape"),
    ("post", "/tool/shape"),
    ("put", "/environment"),
    ("get", "/environment"),
    ("get", "/environment/{obstacle}"),
    ("delete", "/environment"),
    ("delete", "/environment/{obstacle}"),
    ("get", "/version/hardware"),
    ("get", "/version/software"),
    ("get", "/version/software/robot"),
    ("post", "/motors-log"),
    ("put", "/untwisting/finish"),
    ("put", "/jogging"),
    ("post", "/gripper/enable"),
    ("post", "/gripper/disable"),
    ("post", "/stop"),
    ("put", "/stop/bind/{port}/high"),
    ("put", "/stop/bind/{port}/low"),
    ("delete", "/stop"),
    ("put", "/zg/on"),
    ("put", "/zg/off"),
    ("put", "/run/linear/positions"),
    ("put", "/run/linear/poses"),
    ("put", "/run/joint/positions"),
    ("put", "/run/joint/poses"),
}
# Answer in EMERGENCY (SDK 1.8.4's README asks them why a script failed): no 503.
ANSWER_IN_EMERGENCY = {("get", "/status"), ("get", "/status/failure")}
SDK_BODY_OPERATIONS = [
    ("post", "/tool/info"),
    ("post", "/tool/shape"),
    ("put", "/environment"),
    ("put", "/jogging"),
    ("put", "/run/linear/positions"),
    ("put", "/run/linear/poses"),
    ("put", "/run/joint/positions"),
    ("put", "/run/joint/poses"),
]
MOTION_OPERATIONS = [("put", "/position"), ("put", "/pose"), ("put", "/poses/run"), ("put", "/positions/run")]
BODY_OPERATIONS = [*MOTION_OPERATIONS, ("post", "/tool"), ("post", "/base"), *SDK_BODY_OPERATIONS]


@pytest.fixture
def schema(client: TestClient) -> dict[str, Any]:
    response = client.get("/openapi.json")
    assert response.status_code == 200
    return response.json()


def operations(schema: dict[str, Any]) -> dict[tuple[str, str], dict[str, Any]]:
    return {(method, path): op for path, item in schema["paths"].items() for method, op in item.items()}


def test_the_pulse_operations_are_the_references_and_the_sdks(schema: dict[str, Any]) -> None:
    pulse = {key for key, op in operations(schema).items() if TAG_SIM not in op["tags"]}
    assert pulse == PULSE_OPERATIONS | SDK_OPERATIONS
    assert len(pulse) == 53  # the reference's 23 and SDK 1.8.4's 30 more (it never calls GET/POST /tool)


def pdhttp_operations() -> set[tuple[str, str]]:
    """Every (method, path) the installed pdhttp 1.8.4 client can send, read from its generated source."""
    import pdhttp.api

    found: set[tuple[str, str]] = set()
    for module in pkgutil.iter_modules(pdhttp.api.__path__):
        source = inspect.getsource(importlib.import_module(f"pdhttp.api.{module.name}"))
        found |= {(m.lower(), p) for p, m in re.findall(r"'(/[^']*)', '(GET|PUT|POST|DELETE)'", source)}
    return found


def test_every_operation_of_the_real_sdk_is_documented(schema: dict[str, Any]) -> None:
    assert importlib.metadata.version("pdhttp") == "1.8.4"
    sdk = pdhttp_operations()
    assert len(sdk) == 51
    assert sdk <= set(operations(schema))


def test_simulator_routes_are_tagged_apart_under_sim(schema: dict[str, Any]) -> None:
    sim_ops = {key for key, op in operations(schema).items() if TAG_SIM in op["tags"]}
    assert sim_ops
    assert all(path.startswith("/sim/") for _, path in sim_ops)


def test_an_app_in_front_of_another_controller_has_no_sim_routes(sim: Any) -> None:
    with TestClient(create_app(RecordingController(sim))) as client:
        paths = client.get("/openapi.json").json()["paths"]
        assert not [path for path in paths if path.startswith("/sim")]
        assert client.put("/sim/reset").status_code == 404


def test_no_422_is_documented(schema: dict[str, Any]) -> None:
    assert '"422"' not in json.dumps(schema)
    assert "HTTPValidationError" not in json.dumps(schema)


def test_every_pulse_operation_has_a_summary_and_its_arm_errors(schema: dict[str, Any]) -> None:
    for key in PULSE_OPERATIONS | SDK_OPERATIONS:
        op = operations(schema)[key]
        assert op["summary"], key
        errors = (("500", MSG_NOT_RESPONDING), ("503", MSG_EMERGENCY))
        for status, message in errors[:1] if key in ANSWER_IN_EMERGENCY else errors:
            examples = op["responses"][status]["content"]["text/plain"]["examples"]
            assert json.dumps(message) in [example["value"] for example in examples.values()], key


@pytest.mark.parametrize("key", BODY_OPERATIONS)
def test_body_operations_document_the_body_and_400(schema: dict[str, Any], key: tuple[str, str]) -> None:
    op = operations(schema)[key]
    content = op["requestBody"]["content"]["application/json"]
    assert content["schema"] and content["example"]
    examples = op["responses"]["400"]["content"]["text/plain"]["examples"]
    assert json.dumps(MSG_BAD_FORMAT) in [example["value"] for example in examples.values()]


@pytest.mark.parametrize("key", MOTION_OPERATIONS)
def test_motion_parameters_are_documented_with_ranges(schema: dict[str, Any], key: tuple[str, str]) -> None:
    params = {param["name"]: param for param in operations(schema)[key]["parameters"]}
    assert set(params) >= {"speed", "type", "tcp_max_velocity", "motionType", "velocity", "acceleration"}
    # Bounds as Rozum's SDK checks them: above 0 (exclusive); acceleration up to 200 %.
    speed = params["speed"]["schema"]
    assert (speed["exclusiveMinimum"], speed["maximum"]) == (0, 100)
    assert "required" not in params["speed"] or not params["speed"]["required"]
    acceleration = params["acceleration"]["schema"]
    assert (acceleration["exclusiveMinimum"], acceleration["maximum"]) == (0, 200)
    tcp = params["tcp_max_velocity"]["schema"]
    assert (tcp["exclusiveMinimum"], tcp["maximum"], tcp["default"]) == (0, 2, 2)
    assert "412" in operations(schema)[key]["responses"]


def test_ports_are_documented_with_their_ranges(schema: dict[str, Any]) -> None:
    output = operations(schema)[("get", "/signal/output/{port}")]["parameters"][0]["schema"]
    input_ = operations(schema)[("get", "/signal/input/{port}")]["parameters"][0]["schema"]
    assert (output["minimum"], output["maximum"]) == (1, 2)
    assert (input_["minimum"], input_["maximum"]) == (1, 4)


def test_gripper_timeout_defaults_to_500_ms(schema: dict[str, Any]) -> None:
    timeout = operations(schema)[("put", "/gripper/open")]["parameters"][0]
    assert timeout["name"] == "timeout"
    assert timeout["schema"]["default"] == 500


def test_string_results_are_documented_as_plain_text_enums(schema: dict[str, Any]) -> None:
    motion = operations(schema)[("get", "/status/motion")]["responses"]["200"]["content"]["text/plain"]
    assert "IDLE" in motion["schema"]["enum"]
    recover = operations(schema)[("put", "/recover")]["responses"]["200"]["content"]["text/plain"]
    assert recover["schema"]["enum"] == ["SUCCESS", "FAILED"]


@pytest.mark.parametrize(
    "key, model",
    [
        (("get", "/status/failure"), "Failure"),
        (("get", "/robot/info"), "RobotInfo"),
        (("get", "/version/hardware"), "Version"),
        (("get", "/tool/info"), "ToolInfo"),
        (("get", "/tool/shape"), "ToolShape"),
        (("get", "/pose"), "PoseTimestamp"),
        (("get", "/position"), "PositionTimestamp"),
    ],
)
def test_sdk_reads_document_their_model(schema: dict[str, Any], key: tuple[str, str], model: str) -> None:
    content = operations(schema)[key]["responses"]["200"]["content"]["application/json"]
    assert model in json.dumps(content["schema"])
    assert model in schema["components"]["schemas"]


def test_sdk_bodies_and_obstacles_are_in_the_schema(schema: dict[str, Any]) -> None:
    components = schema["components"]["schemas"]
    for name in ("BoxObstacle", "CapsuleObstacle", "PlaneObstacle", "LinearMotionParameters"):
        assert name in components, name
    waypoint = components["PositionWaypoint"]["properties"]
    assert {"blend", "actions"} <= set(waypoint)
    state = operations(schema)[("get", "/status")]["responses"]["200"]["content"]["application/json"]
    assert "EMERGENCY" in state["schema"]["enum"]


def test_the_docs_page_is_served(client: TestClient) -> None:
    response = client.get("/docs")
    assert response.status_code == 200
    assert "swagger" in response.text.lower()
