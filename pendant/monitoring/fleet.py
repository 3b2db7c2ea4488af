"""A site of simulated arms on loopback: N pendants, a real Prometheus and a real Alertmanager started with
the site's own files in deploy/ (scrape configuration, alert rules, routing). `make fleet N=3` runs it for
operators to see what the monitoring gives them; the end-to-end test runs it with shorter timings.

Prometheus and Alertmanager are Debian's binaries (`prometheus`, `prometheus-alertmanager`), found on PATH.
"""

from __future__ import annotations

import argparse
import contextlib
import functools
import json
import shutil
import socket
import subprocess
import sys
import tempfile
import threading
import time
import urllib.parse
import urllib.request
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass, field
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path
from typing import Any

import yaml

from pendant.paths import deploy_dir

LOOPBACK = "127.0.0.1"
START_TIMEOUT_S = 120.0  # three pendants starting at once on a loaded 2-core machine
STOP_TIMEOUT_S = 10.0


@dataclass(frozen=True)
class Timings:
    """How fast the site reacts. The defaults are deploy/'s own; tests shorten them."""

    scrape_interval: str = "5s"
    alert_for: str | None = None  # None: each rule's own `for:`
    group_wait: str | None = None  # None: Alertmanager routing's own


@dataclass
class Site:
    """Where everything answers once the fleet is up."""

    pendant_apis: list[str]
    pendant_uis: list[str]
    prometheus: str
    alertmanager: str
    webhook: str
    alerts: list[dict[str, Any]] = field(default_factory=list)  # the webhook's JSON, in the order it came


def free_port() -> int:
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as probe:
        probe.bind((LOOPBACK, 0))
        return int(probe.getsockname()[1])


def prometheus_config(targets: Sequence[str], alertmanager: str, timings: Timings) -> dict[str, object]:
    """deploy/prometheus/prometheus.yml with this site's targets and Alertmanager."""
    config = yaml.safe_load((deploy_dir() / "prometheus" / "prometheus.yml").read_text())
    config["global"]["scrape_interval"] = timings.scrape_interval
    config["global"]["evaluation_interval"] = timings.scrape_interval
    config["alerting"]["alertmanagers"][0]["static_configs"][0]["targets"] = [alertmanager]
    config["scrape_configs"][0]["static_configs"][0]["targets"] = list(targets)
    return config


def alert_rules(timings: Timings) -> dict[str, Any]:  # YAML, as Prometheus reads it
    rules = yaml.safe_load((deploy_dir() / "prometheus" / "pulse-alerts.yml").read_text())
    if timings.alert_for is not None:
        for group in rules["groups"]:
            for rule in group["rules"]:
                if "for" in rule:
                    rule["for"] = timings.alert_for
    return rules


def alertmanager_config(webhook: str, timings: Timings) -> dict[str, object]:
    """deploy/alertmanager/alertmanager.yml delivering to `webhook`."""
    config = yaml.safe_load((deploy_dir() / "alertmanager" / "alertmanager.yml").read_text())
    for receiver in config["receivers"]:
        for hook in receiver.get("webhook_configs", []):
            hook["url"] = webhook
    if timings.group_wait is not None:
        routes = [config["route"], *config["route"].get("routes", [])]
        for route in routes:
            route["group_wait"] = timings.group_wait
            route["group_interval"] = timings.group_wait
    return config


def _binary(name: str) -> str:
    found = shutil.which(name)
    if found is None:
        raise FileNotFoundError(f"{name} not found: install Debian's prometheus and prometheus-alertmanager")
    return found


def _wait(ready: Callable[[], bool], what: str, process: subprocess.Popen[bytes]) -> None:
    deadline = time.monotonic() + START_TIMEOUT_S
    while time.monotonic() < deadline:
        if process.poll() is not None:
            raise RuntimeError(f"{what} exited with {process.returncode} before it answered")
        try:
            if ready():
                return
        except OSError:
            pass
        time.sleep(0.1)
    raise TimeoutError(f"{what} did not answer within {START_TIMEOUT_S:g} s")


def _answers(url: str) -> bool:
    with urllib.request.urlopen(url, timeout=2.0) as response:
        return bool(response.status == 200)


class _Webhook(BaseHTTPRequestHandler):
    site: Site
    echo: bool

    def do_POST(self) -> None:
        length = min(int(self.headers.get("Content-Length", "0")), 1 << 20)
        payload = json.loads(self.rfile.read(length) or b"{}")
        for alert in payload.get("alerts", []):
            self.site.alerts.append(alert)
            if self.echo:
                labels = alert.get("labels", {})
                print(f"ALERT {alert.get('status')}: {labels.get('alertname')} on {labels.get('instance')}")
        self.send_response(200)
        self.end_headers()

    def log_message(self, format: str, *args: object) -> None:
        pass


@contextlib.contextmanager
def running_fleet(
    pendants: int,
    *,
    timings: Timings = Timings(),
    with_ui: bool = False,
    echo_alerts: bool = False,
    workdir: Path | None = None,
) -> Iterator[Site]:
    """Start the site, yield where it answers, stop every process on exit (also on Ctrl-C)."""
    if not 1 <= pendants <= 10:
        raise ValueError("a fleet has 1 to 10 pendants")
    with contextlib.ExitStack() as stack:
        root = workdir or Path(stack.enter_context(tempfile.TemporaryDirectory(prefix="pulse-fleet-")))
        processes: list[subprocess.Popen[bytes]] = []
        stack.callback(_stop_all, processes)

        webhook_port, prometheus_port, alertmanager_port = free_port(), free_port(), free_port()
        site = Site(
            [],
            [],
            f"http://{LOOPBACK}:{prometheus_port}",
            f"http://{LOOPBACK}:{alertmanager_port}",
            f"http://{LOOPBACK}:{webhook_port}/alerts",
        )
        handler = type("Webhook", (_Webhook,), {"site": site, "echo": echo_alerts})
        server = ThreadingHTTPServer((LOOPBACK, webhook_port), handler)
        threading.Thread(target=server.serve_forever, name="fleet-webhook", daemon=True).start()
        stack.callback(server.shutdown)

        for index in range(pendants):
            api_port = free_port()
            command = [sys.executable, "-m", "pendant", "--host", LOOPBACK, "--api-port", str(api_port)]
            command += ["--data", str(root / f"pendant-{index + 1}")]
            command += ["--programs", str(root / f"programs-{index + 1}")]
            if with_ui:
                ui_port = free_port()
                command += ["--ui-port", str(ui_port)]
                site.pendant_uis.append(f"http://{LOOPBACK}:{ui_port}")
            else:
                command.append("--no-ui")
            processes.append(subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL))
            site.pendant_apis.append(f"http://{LOOPBACK}:{api_port}")

        # Prometheus starts once every pendant answers, or its first scrapes would page "pendant down".
        for api, process in zip(site.pendant_apis, processes, strict=False):
            metrics = f"{api}/metrics"
            _wait(functools.partial(_answers, metrics), f"the pendant at {api}", process)
        (root / "alertmanager.yml").write_text(yaml.safe_dump(alertmanager_config(site.webhook, timings)))
        alertmanager = [_binary("prometheus-alertmanager"), f"--config.file={root / 'alertmanager.yml'}"]
        alertmanager += [f"--storage.path={root / 'alertmanager-data'}", "--cluster.listen-address="]
        alertmanager += [f"--web.listen-address={LOOPBACK}:{alertmanager_port}"]
        processes.append(subprocess.Popen(alertmanager, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL))

        targets = [api.removeprefix("http://") for api in site.pendant_apis]
        config = prometheus_config(targets, f"{LOOPBACK}:{alertmanager_port}", timings)
        (root / "prometheus.yml").write_text(yaml.safe_dump(config))
        (root / "pulse-alerts.yml").write_text(yaml.safe_dump(alert_rules(timings), allow_unicode=True))
        prometheus = [_binary("prometheus"), f"--config.file={root / 'prometheus.yml'}"]
        prometheus += [f"--storage.tsdb.path={root / 'prometheus-data'}"]
        prometheus += [f"--web.listen-address={LOOPBACK}:{prometheus_port}"]
        processes.append(subprocess.Popen(prometheus, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL))

        _wait(lambda: _answers(f"{site.alertmanager}/-/ready"), "Alertmanager", processes[-2])
        _wait(lambda: _answers(f"{site.prometheus}/-/ready"), "Prometheus", processes[-1])
        yield site


def _stop_all(processes: list[subprocess.Popen[bytes]]) -> None:
    for process in processes:
        if process.poll() is None:
            process.terminate()
    for process in processes:
        try:
            process.wait(STOP_TIMEOUT_S)
        except subprocess.TimeoutExpired:
            process.kill()


def query(prometheus: str, expr: str) -> list[dict[str, Any]]:  # JSON, as Prometheus answers
    """An instant PromQL query's result vector."""
    url = f"{prometheus}/api/v1/query?" + urllib.parse.urlencode({"query": expr})
    with urllib.request.urlopen(url, timeout=5.0) as response:
        body = json.load(response)
    if body.get("status") != "success":
        raise RuntimeError(f"{expr}: {body.get('error')}")
    return list(body["data"]["result"])


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="make fleet", description=__doc__.splitlines()[0])
    parser.add_argument("--pendants", type=int, default=3, help="how many simulated arms (1-10, default 3)")
    args = parser.parse_args(argv)
    try:
        with running_fleet(args.pendants, with_ui=True, echo_alerts=True) as site:
            for index, (ui, api) in enumerate(zip(site.pendant_uis, site.pendant_apis, strict=True)):
                print(f"arm {index + 1}: pendant {ui}  API {api}  metrics {api}/metrics")
            print(f"Prometheus   {site.prometheus}  (alerts: {site.prometheus}/alerts)")
            print(f"Alertmanager {site.alertmanager}")
            print(f"Alerts delivered to {site.webhook} are printed here. Ctrl-C stops all.")
            print(f"Try a fault: curl -X PUT {site.pendant_apis[0]}/sim/fault/overheat", flush=True)
            while True:
                time.sleep(1.0)
    except KeyboardInterrupt:
        print("fleet stopped")
    return 0


if __name__ == "__main__":
    sys.exit(main())
