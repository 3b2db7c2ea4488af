"""One APIRouter per PULSE resource; each is built for one controller (no module-level state)."""
