"""Teach and play back: a waypoint table and a step tree (pydantic), versioned JSON files, the runner (one
interpreter for the page and `pendant run`), Python export."""

from pendant.paths import DEFAULT_PROGRAMS_DIR, PROGRAMS_DIR_ENV, programs_dir
from pendant.program.describe import describe_step
from pendant.program.editing import EditError
from pendant.program.export import export_script, program_operations
from pendant.program.files import (
    ProgramFileError,
    ProgramStore,
    atomic_write,
    parse_program,
    sanitize_name,
)
from pendant.program.models import (
    SCHEMA_VERSION,
    CallStep,
    CommentStep,
    Frame,
    GripperAction,
    GripperAtWaypoint,
    GripperStep,
    IfStep,
    LoopMode,
    LoopStep,
    MoveStep,
    Offset,
    OutputAction,
    OutputStep,
    PalletStep,
    PathPoint,
    PathStep,
    Program,
    Step,
    WaitInputStep,
    WaitStep,
    Waypoint,
)
from pendant.program.plan import PlanError, compile_program
from pendant.program.runner import ProgramRunner, RunnerBusy, RunProgress, RunState
from pendant.program.workspace import Change, ProgramWorkspace

__all__ = [
    "DEFAULT_PROGRAMS_DIR",
    "PROGRAMS_DIR_ENV",
    "SCHEMA_VERSION",
    "CallStep",
    "Change",
    "CommentStep",
    "EditError",
    "Frame",
    "GripperAction",
    "GripperAtWaypoint",
    "GripperStep",
    "IfStep",
    "LoopMode",
    "LoopStep",
    "MoveStep",
    "Offset",
    "OutputAction",
    "OutputStep",
    "PalletStep",
    "PathPoint",
    "PathStep",
    "PlanError",
    "Program",
    "ProgramFileError",
    "ProgramRunner",
    "ProgramStore",
    "ProgramWorkspace",
    "RunProgress",
    "RunState",
    "RunnerBusy",
    "Step",
    "WaitInputStep",
    "WaitStep",
    "Waypoint",
    "atomic_write",
    "compile_program",
    "describe_step",
    "export_script",
    "parse_program",
    "program_operations",
    "programs_dir",
    "sanitize_name",
]
