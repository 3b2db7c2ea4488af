"""The test kit: what many tests (and the benchmarks) share, kept once.

- `ports`: `LOOPBACK`, `free_port()`, `wait_for_port()`
- `waiting`: `wait_until()` (poll a real process on a real clock), `answers()`
- `launchers`: real `pendant` processes: `running_pendant()` (API only), `running_pendant_ui()` (page and
  API), `pendant_process()`, the `launch` fixture's `Launcher`; `REPO_ROOT`
- `threads`: `serve_in_thread()`, an ASGI app served by uvicorn on loopback from a thread
- `pages`: `pendant_page()` (a PendantUI on a free port, stopped after), `headless_session()`
- `doubles`: stand-ins for a browser (`FakeBrowser`, `OPERATOR`, `VIEWER`, `fire`)
- `fixtures`: the fixtures every test directory may use (`pendant_ui`, `ui`, `controller` for the
  contract suites, `remote`, `launch`), registered by tests/conftest.py
"""
