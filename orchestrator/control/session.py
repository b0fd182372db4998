"""zenoh sessions for the master (listens) and the controller (connects).

Defaults are closed: peer mode, listening on loopback only, multicast scouting off, so nothing
outside this machine sees or reaches the run. Anything else (other endpoints, TLS, access
control) comes from a zenoh configuration file the user passes, used as is.
"""

from __future__ import annotations

import json
from pathlib import Path

import zenoh

DEFAULT_ENDPOINT = "tcp/127.0.0.1:7447"


def _config(role: str, endpoints: list[str], config_file: str | Path | None) -> zenoh.Config:
    if config_file:
        path = Path(config_file)
        if not path.is_file():
            raise FileNotFoundError(f"zenoh configuration file {path} does not exist")
        return zenoh.Config.from_file(str(path))
    conf = zenoh.Config()
    conf.insert_json5("mode", '"peer"')
    conf.insert_json5("scouting/multicast/enabled", "false")
    conf.insert_json5(f"{role}/endpoints", json.dumps(list(endpoints)))
    if role == "connect":
        conf.insert_json5("listen/endpoints", "[]")
    return conf


def open_master(endpoints: list[str] | None = None, config_file: str | Path | None = None) -> zenoh.Session:
    """Session of the master: listens on ``endpoints`` (default loopback port 7447)."""
    return zenoh.open(_config("listen", endpoints or [DEFAULT_ENDPOINT], config_file))


def open_controller(endpoints: list[str] | None = None, config_file: str | Path | None = None) -> zenoh.Session:
    """Session of a controller: connects to the master's ``endpoints``."""
    return zenoh.open(_config("connect", endpoints or [DEFAULT_ENDPOINT], config_file))
