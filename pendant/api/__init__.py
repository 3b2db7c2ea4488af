"""The PULSE REST API over HTTP: `create_app(controller)`; no robot logic lives here."""

from pendant.api.app import create_app

__all__ = ["create_app"]
