"""Teach and play back: waypoints and programs (pydantic), versioned JSON files, the runner, Python export."""

from pendant.program.export import export_script, program_operations
from pendant.program.files import (
    DEFAULT_PROGRAMS_DIR,
    PROGRAMS_DIR_ENV,
    ProgramFileError,
    ProgramStore,
    atomic_write,
    parse_program,
    programs_dir,
    sanitize_name,
)
from pendant.program.models import (
    SCHEMA_VERSION,
    GripperAction,
    GripperStep,
    MoveStep,
    OutputStep,
    Program,
    Step,
    WaitInputStep,
    WaitStep,
    Waypoint,
    describe_step,
)
from pendant.program.plan import MoveGroup, SingleStep, plan_segments
from pendant.program.runner import ProgramRunner, RunnerBusy, RunProgress, RunState
from pendant.program.workspace import Change, EditError, ProgramWorkspace

__all__ = [
    "DEFAULT_PROGRAMS_DIR",
    "PROGRAMS_DIR_ENV",
    "SCHEMA_VERSION",
    "Change",
    "EditError",
    "GripperAction",
    "GripperStep",
    "MoveGroup",
    "MoveStep",
    "OutputStep",
    "Program",
    "ProgramFileError",
    "ProgramRunner",
    "ProgramStore",
    "ProgramWorkspace",
    "RunProgress",
    "RunState",
    "RunnerBusy",
    "SingleStep",
    "Step",
    "WaitInputStep",
    "WaitStep",
    "Waypoint",
    "atomic_write",
    "describe_step",
    "export_script",
    "parse_program",
    "plan_segments",
    "program_operations",
    "programs_dir",
    "sanitize_name",
]
