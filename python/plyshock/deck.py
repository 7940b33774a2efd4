"""YAML decks: the same keys as the Python objects (scene.py).  SI units.

    dimension: 2                # 2 = plane strain (per metre of depth), or 3
    grid: {lower: [...], upper: [...], cells: [...], boundary: {x-: free, ...}}
    materials: [{name: cfrp, preset: IM7/8552}, ...]
    bodies: [{name: plate, laminate: {frame: ..., size: ..., plies|layup: ...}}, ...]
"""
import yaml

from .errors import DeckError
from .scene import Scene


def load_text(text, source="<deck>"):
    """A validated Scene from deck text."""
    try:
        d = yaml.safe_load(text)
    except yaml.YAMLError as e:
        raise DeckError("", f"{source} is not valid YAML: {e}") from None
    if not isinstance(d, dict):
        raise DeckError("", f"{source} must be a mapping with keys dimension, grid, materials, bodies")
    return Scene.from_dict(d).validate()


def load(path):
    """A validated Scene and the deck text from a YAML file."""
    try:
        with open(path) as f:
            text = f.read()
    except OSError as e:
        raise DeckError("", f"cannot read deck {path}: {e.strerror}") from None
    return load_text(text, path), text
