"""The `pendant` command line: flags become Settings (bad ones are refused with a usage message), the link
timeouts reach the remote client, and what start-up prints about the access token."""

from __future__ import annotations

from urllib.parse import parse_qs, urlsplit

import pytest

from pendant.access import TOKEN_HEADER, TOKEN_QUERY
from pendant.cli import announce, make_controller, parse_settings, with_access_token
from pendant.config import Settings
from pendant.remote import RemoteController
from pendant.remote.client import DEFAULT_CONNECT_TIMEOUT_S, DEFAULT_READ_TIMEOUT_S

ROBOT_URL = "http://127.0.0.1:9"  # discard port: nothing is sent in these tests


def test_defaults_serve_the_simulated_pulse75_on_the_controllers_port() -> None:
    assert parse_settings([]) == Settings()
    assert (Settings().host, Settings().api_port, Settings().ui_port) == ("127.0.0.1", 8081, 8080)


def test_every_flag_lands_in_settings() -> None:
    argv = [
        "--no-ui",
        "--host",
        "0.0.0.0",
        "--api-port",
        "9000",
        "--ui-port",
        "9001",
        "--model",
        "pulse90",
        "--robot",
        "http://10.0.0.2:8081",
        "--token",
        "s3cret",
        "--environment-map",
        "studio",
    ]
    assert parse_settings(argv) == Settings(
        host="0.0.0.0",
        ui_port=9001,
        api_port=9000,
        model="pulse90",
        robot_url="http://10.0.0.2:8081",
        no_ui=True,
        token="s3cret",
        environment_map="studio",
    )


@pytest.mark.parametrize(
    "argv",
    [["--model", "pulse60"], ["--api-port", "http"], ["--api-port", "70000"], ["--environment-map", "moon"]],
)
def test_bad_flags_exit_with_usage(argv: list[str], capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as exit_info:
        parse_settings(argv)
    assert exit_info.value.code == 2
    assert "usage: pendant" in capsys.readouterr().err


def test_start_up_prints_where_the_api_is(capsys: pytest.CaptureFixture[str]) -> None:
    announce(Settings(api_port=9123, no_ui=True))
    out = capsys.readouterr().out
    assert "http://127.0.0.1:9123" in out
    assert "http://127.0.0.1:9123/docs" in out


# Timeouts


def test_timeouts_default_to_one_and_three_seconds_as_the_client() -> None:
    settings = parse_settings([])
    assert (settings.connect_timeout, settings.read_timeout) == (1.0, 3.0)
    assert (settings.connect_timeout, settings.read_timeout) == (
        DEFAULT_CONNECT_TIMEOUT_S,
        DEFAULT_READ_TIMEOUT_S,
    )


def test_timeout_flags_land_in_settings() -> None:
    settings = parse_settings(["--robot", ROBOT_URL, "--connect-timeout", "0.25", "--read-timeout", "7"])
    assert (settings.connect_timeout, settings.read_timeout) == (0.25, 7.0)


@pytest.mark.parametrize("value", ["0", "-1", "soon", "inf", "nan"])
@pytest.mark.parametrize("flag", ["--connect-timeout", "--read-timeout"])
def test_a_timeout_that_is_not_a_positive_number_exits_with_usage(
    flag: str, value: str, capsys: pytest.CaptureFixture[str]
) -> None:
    with pytest.raises(SystemExit) as exit_info:
        parse_settings([flag, value])
    assert exit_info.value.code == 2
    err = capsys.readouterr().err
    assert "usage: pendant" in err
    assert flag in err


def test_the_robot_client_gets_the_configured_timeouts() -> None:
    settings = parse_settings(["--robot", ROBOT_URL, "--connect-timeout", "0.4", "--read-timeout", "2.5"])
    controller = make_controller(settings)
    try:
        assert isinstance(controller, RemoteController)
        assert (controller.connect_timeout, controller.read_timeout) == (0.4, 2.5)
    finally:
        assert isinstance(controller, RemoteController)
        controller.close()


# Access token at start-up


def printed_ui_url(out: str) -> str:
    """The URL line printed under "Open the pendant ... with this URL:"."""
    lines = out.splitlines()
    index = next(i for i, line in enumerate(lines) if line.startswith("Open the pendant"))
    return lines[index + 1].strip()


def token_in_url(url: str) -> str:
    """The token the page will send (its script hands `?token=` to the websocket the page connects to)."""
    return parse_qs(urlsplit(url).query)[TOKEN_QUERY][0]


def test_an_exposed_pendant_prints_a_fresh_token_its_url_and_the_api_header(
    capsys: pytest.CaptureFixture[str],
) -> None:
    settings = with_access_token(parse_settings(["--host", "0.0.0.0", "--ui-port", "9001"]))
    assert settings.token
    announce(settings)
    out = capsys.readouterr().out
    assert f"Access token: {settings.token}" in out
    url = printed_ui_url(out)
    assert url.startswith("http://") and ":9001/" in url
    assert token_in_url(url) == settings.token
    assert f"{TOKEN_HEADER}: {settings.token}" in out


def test_each_exposed_start_generates_a_different_token() -> None:
    first = with_access_token(parse_settings(["--host", "0.0.0.0"])).token
    second = with_access_token(parse_settings(["--host", "0.0.0.0"])).token
    assert first and second and first != second


def test_a_given_token_is_used_as_it_is(capsys: pytest.CaptureFixture[str]) -> None:
    settings = with_access_token(parse_settings(["--host", "0.0.0.0", "--token", "T"]))
    assert settings.token == "T"
    announce(settings)
    out = capsys.readouterr().out
    assert "Access token: T" in out
    assert token_in_url(printed_ui_url(out)) == "T"
    assert f"{TOKEN_HEADER}: T" in out


def test_an_exposed_api_alone_prints_the_header_but_no_page_url(capsys: pytest.CaptureFixture[str]) -> None:
    settings = with_access_token(parse_settings(["--host", "0.0.0.0", "--no-ui"]))
    announce(settings)
    out = capsys.readouterr().out
    assert f"{TOKEN_HEADER}: {settings.token}" in out
    assert "Open the pendant" not in out


@pytest.mark.parametrize("host", ["127.0.0.1", "localhost", "::1"])
def test_loopback_gets_no_token(host: str, capsys: pytest.CaptureFixture[str]) -> None:
    settings = with_access_token(parse_settings(["--host", host]))
    assert settings.token is None
    announce(settings)
    out = capsys.readouterr().out
    assert "token" not in out.lower()
    assert TOKEN_HEADER not in out


def test_a_token_given_on_loopback_is_kept() -> None:
    assert with_access_token(Settings(token="T")).token == "T"
