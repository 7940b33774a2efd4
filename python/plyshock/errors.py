"""Errors in a scene description: each names the deck key path and what is allowed."""
import difflib


class DeckError(ValueError):
    """Bad input.  `path` is the deck key path (e.g. bodies[0].laminate.plies[2].thickness)."""

    def __init__(self, path, message):
        self.path = path
        self.message = message
        super().__init__(f"{path}: {message}" if path else message)


def check_keys(d, allowed, path):
    """Unknown keys are an error that suggests the nearest valid one."""
    if not isinstance(d, dict):
        raise DeckError(path, f"must be a mapping with keys from {sorted(allowed)}, got {type(d).__name__}")
    for k in d:
        if k not in allowed:
            near = difflib.get_close_matches(str(k), list(allowed), n=1)
            hint = f"; did you mean '{near[0]}'?" if near else ""
            raise DeckError(f"{path}.{k}" if path else str(k), f"unknown key{hint} (allowed: {', '.join(sorted(allowed))})")


def number(v, path, lo=None, hi=None, lo_open=False, integer=False):
    """A real (or integer) in [lo, hi] (lo excluded when lo_open)."""
    if isinstance(v, bool) or not isinstance(v, (int, float)):
        try:
            v = float(v) if not integer else int(v)
        except (TypeError, ValueError):
            raise DeckError(path, f"must be a {'whole ' if integer else ''}number, got {v!r}") from None
    if integer and int(v) != v:
        raise DeckError(path, f"must be a whole number, got {v!r}")
    v = int(v) if integer else float(v)
    if v != v or v in (float("inf"), float("-inf")):
        raise DeckError(path, f"must be finite, got {v}")
    rng = f"{'(' if lo_open else '['}{'-inf' if lo is None else lo}, {'inf' if hi is None else hi}]"
    if lo is not None and (v < lo or (lo_open and v == lo)):
        raise DeckError(path, f"{v} is out of range; allowed {rng}")
    if hi is not None and v > hi:
        raise DeckError(path, f"{v} is out of range; allowed {rng}")
    return v


def vector(v, n, path):
    """A list of n finite numbers."""
    if not isinstance(v, (list, tuple)) or len(v) != n:
        raise DeckError(path, f"must be a list of {n} numbers, got {v!r}")
    return [number(x, f"{path}[{i}]") for i, x in enumerate(v)]
