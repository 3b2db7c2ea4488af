"""JSON bodies of the pendant's own routes, bounded before they are parsed: nesting depth (issue #32).

Python's JSON parser and pydantic recurse once per level: a body nested ~1,000 deep raised RecursionError,
answered 500 with a traceback and was neither logged nor counted as a refusal. The depth is found first by a
scan of the brackets outside strings (strings are skipped whole by one regular expression), so such a body
is a 400 with the reason, like any other malformed body.
"""

from __future__ import annotations

import json
import re

# A program nests steps at most 16 deep (two JSON levels each) inside its document: 64 is far above any.
MAX_JSON_DEPTH = 64
MSG_TOO_DEEP = "the body nests more than {limit} levels deep ({{ and [ inside each other)"
_TOKENS = re.compile(rb'"[^"\\]*(?:\\.[^"\\]*)*"|[\[\]{}]')
_OPENERS = frozenset(b"[{")


def json_depth(body: bytes, limit: int = MAX_JSON_DEPTH) -> int:
    """The body's nesting depth, counted up to `limit` + 1 (the scan stops there)."""
    depth = deepest = 0
    for token in _TOKENS.finditer(body):
        first = body[token.start()]
        if first in _OPENERS:
            depth += 1
            if depth > deepest:
                deepest = depth
                if deepest > limit:
                    break
        elif first != 0x22:  # a closer (a string starts with a quote)
            depth -= 1
    return deepest


def load_json(body: bytes, max_depth: int = MAX_JSON_DEPTH) -> object:
    """The parsed body, or ValueError saying what is wrong (not JSON, or nested deeper than `max_depth`)."""
    if json_depth(body, max_depth) > max_depth:
        raise ValueError(MSG_TOO_DEEP.format(limit=max_depth))
    try:
        return json.loads(body)
    except RecursionError:  # not reached below the depth limit; kept so no body can answer 500
        raise ValueError(MSG_TOO_DEEP.format(limit=max_depth)) from None
    except ValueError as error:  # JSONDecodeError and UnicodeDecodeError are ValueErrors
        raise ValueError(f"the body is not JSON: {error}") from None
