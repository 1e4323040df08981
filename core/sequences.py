"""`common_ends`: how far two versions of a sequence agree from the front and from the back — how the live
editor's next parse, run and answer find the few lines a keystroke changed (core/syntax/parser.py,
core/interpreter/checkpoints.py, server/jobs.py)."""

from __future__ import annotations

import operator
from collections.abc import Callable, Sequence
from typing import Any


def common_ends(
    old: Sequence[Any], new: Sequence[Any], same: Callable[[Any, Any], bool] = operator.eq
) -> tuple[int, int]:
    """(prefix, suffix): the lengths of the longest common prefix and, in what is left of the shorter one, the
    longest common suffix of `old` and `new`, by `same`. `map` walks both sequences at C speed where `same` is
    one of the operator module's (`operator.eq`, `operator.is_`)."""
    limit = min(len(old), len(new))
    agree = list(map(same, old, new))
    prefix = agree.index(False) if False in agree else limit
    agree = list(map(same, reversed(old), reversed(new)))
    suffix = agree.index(False) if False in agree else limit
    return prefix, min(suffix, limit - prefix)
