"""YAML decks: the same keys as the Python objects (scene.py).  SI units.

    dimension: 2                # 2 = plane strain (per metre of depth), or 3
    grid: {lower: [...], upper: [...], cells: [...], boundary: {x-: free, ...}}
    materials: [{name: cfrp, preset: IM7/8552}, ...]
    bodies: [{name: plate, laminate: {frame: ..., size: ..., plies|layup: ...}}, ...]
"""
import os

import yaml

from .errors import DeckError
from .scene import Scene


MAX_BYTES = 16 * 2**20     # a deck is a page of text; anything this large is not one


def load_text(text, source="<deck>"):
    """A validated Scene from deck text."""
    try:
        d = yaml.safe_load(text)
    except yaml.YAMLError as e:
        raise DeckError("", f"{source} is not valid YAML: {e}") from None
    except (ValueError, TypeError, OverflowError, RecursionError) as e:     # e.g. a date like 2024-13-45, nesting too deep
        raise DeckError("", f"{source} is not a valid deck: YAML cannot read a value ({type(e).__name__}: {e})") from None
    if not isinstance(d, dict):
        kind = "empty" if d is None else f"a {type(d).__name__}"
        raise DeckError("", f"{source} must be a mapping with keys dimension, grid, materials, bodies; it is {kind}")
    return Scene.from_dict(d).validate()


def read_text(path):
    """A deck file's text, or DeckError when it cannot be read or is not UTF-8 text."""
    try:
        if os.path.getsize(path) > MAX_BYTES:
            raise DeckError("", f"{path} is {os.path.getsize(path)} bytes: not a deck (a YAML text file of at most {MAX_BYTES} bytes)")
        with open(path, "rb") as f:
            raw = f.read()
    except OSError as e:
        raise DeckError("", f"cannot read deck {path}: {e.strerror}") from None
    if b"\0" in raw:
        raise DeckError("", f"{path} is not a text file (it holds NUL bytes, from offset {raw.index(0)}); a deck is YAML text")
    try:
        return raw.decode("utf-8")
    except UnicodeDecodeError as e:
        raise DeckError("", f"{path} is not a text file (byte 0x{raw[e.start]:02x} at offset {e.start} is not UTF-8); "
                        f"a deck is YAML text") from None


def load(path):
    """A validated Scene and the deck text from a YAML file."""
    text = read_text(path)
    return load_text(text, path), text
