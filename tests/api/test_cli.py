"""The `pendant` command line: flags become Settings; bad flags are refused with a usage message."""

from __future__ import annotations

import pytest

from pendant.cli import announce, parse_settings
from pendant.config import Settings


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
    ]
    assert parse_settings(argv) == Settings(
        host="0.0.0.0",
        ui_port=9001,
        api_port=9000,
        model="pulse90",
        robot_url="http://10.0.0.2:8081",
        no_ui=True,
        token="s3cret",
    )


@pytest.mark.parametrize("argv", [["--model", "pulse60"], ["--api-port", "http"], ["--api-port", "70000"]])
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
