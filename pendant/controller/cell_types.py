"""The cell as Rozum's SDK 1.5-1.8.4 describes it: the tool's two views and the obstacles (metres, radians).

Wire names are the SDK's (camelCase where it uses camelCase); see reference/pulse-api-1.8.md.
"""

from __future__ import annotations

from typing import Annotated, Literal

from pydantic import BaseModel, ConfigDict, Field, field_validator

from pendant.controller.types import TOOL_NAME_MAX, FiniteFloat, Point, Position

NAME_MAX_CHARS = 200
MAX_TOOL_CAPSULES = 16
MAX_OBSTACLES = 100
MAX_PLANE_POINTS = 16

MSG_NO_OBSTACLE = "No obstacle named {name!r} in the environment"
MSG_TOO_MANY_OBSTACLES = f"environment must hold at most {MAX_OBSTACLES} obstacles: remove some first"
MSG_PLANE_ON_A_LINE = "plane points must not lie on one line"
MSG_OBSTACLE_TOUCHES_ARM = (
    "Collision detected: the obstacle touches the arm or its tool while it moves (freeze it first)"
)
MSG_SHAPE_TOUCHES = "Collision detected: the tool shape would touch an obstacle or the floor where the arm is"

Name = Annotated[str, Field(min_length=1, max_length=NAME_MAX_CHARS)]
Radius = Annotated[FiniteFloat, Field(ge=0.0)]


class _Strict(BaseModel):
    model_config = ConfigDict(strict=True, frozen=True, populate_by_name=True)


class ToolInfo(_Strict):
    """The tool as GET/POST /tool/info: its name and the TCP's pose relative to the flange centre."""

    name: Annotated[str, Field(max_length=TOOL_NAME_MAX)]  # the same tool as /tool: the same bound
    tcp: Position


class SimplifiedCapsuleObstacle(_Strict):
    """A capsule of the tool, in the flange frame: a segment `begin`-`finish` swept by a sphere."""

    radius: Radius
    begin: Point
    finish: Point


class ToolShape(_Strict):
    """The tool's geometry for collision checks: capsules attached to the flange."""

    shape: Annotated[list[SimplifiedCapsuleObstacle], Field(max_length=MAX_TOOL_CAPSULES)]


class BoxObstacle(_Strict):
    obstacleType: Literal["BOX"]
    name: Name
    sides: Point  # edge lengths along the box's own x, y, z
    centerPosition: Position  # in the arm's base frame

    @field_validator("sides")
    @classmethod
    def _sides_positive(cls, sides: Point) -> Point:
        # A box of zero or negative size is a typo, not an obstacle (it would guard nothing).
        if min(sides.x, sides.y, sides.z) <= 0:
            raise ValueError(
                f"box sides must be greater than 0 m (got x={sides.x:g}, y={sides.y:g}, z={sides.z:g})"
            )
        return sides


class CapsuleObstacle(_Strict):
    obstacleType: Literal["CAPSULE"]
    name: Name
    radius: Radius
    begin: Point
    finish: Point


class PlaneObstacle(_Strict):
    """The plane through the first three `points`; the side away from the arm base is solid."""

    obstacleType: Literal["PLANE"]
    name: Name
    points: Annotated[list[Point], Field(min_length=3, max_length=MAX_PLANE_POINTS)]


Obstacle = Annotated[BoxObstacle | CapsuleObstacle | PlaneObstacle, Field(discriminator="obstacleType")]
