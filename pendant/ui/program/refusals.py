"""What a Program-tab action may refuse with: told to the browser that asked, nothing changed."""

from pendant.program import EditError, PlanError, ProgramFileError, RunnerBusy

USER_ERRORS = (EditError, ProgramFileError, PlanError, RunnerBusy, OSError, ValueError)
