#!/bin/sh
# Move J1 to 30 degrees with curl, wait until the arm is still, print the pose.
# Usage: PULSE_URL=http://127.0.0.1:8081 sh examples/move.sh   (the default is make run's API)
set -eu
URL="${PULSE_URL:-http://127.0.0.1:8081}"

curl -sf -X PUT "$URL/pose?speed=30" -H 'Content-Type: application/json' \
    -d '{"angles": [30, -90, 90, -90, -90, 0]}'
# GET /status/motion answers a JSON string: "RUNNING" while the arm moves, "IDLE" once it is still.
while [ "$(curl -sf "$URL/status/motion")" = '"RUNNING"' ]; do sleep 0.1; done
echo "status: $(curl -sf "$URL/status/motion")"
echo "pose: $(curl -sf "$URL/pose")"
