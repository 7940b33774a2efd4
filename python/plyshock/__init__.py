"""plyshock: exact layered-composite markers and shock-physics MPM on PETSc.

Units are SI throughout: m, kg, s, Pa, K (2D scenes are plane strain, per metre
of depth).  Scene objects: Scene, Grid, Material, Frame, Ply, Laminate, Box,
Sphere, Cylinder, Body, Contact; decks: plyshock.deck.load().
"""
from .errors import DeckError
from .layup import parse_layup
from .scene import Body, Box, Contact, Cylinder, Frame, Grid, Interface, Laminate, Material, Ply, Run, Scene, Sphere

__version__ = "0.1.0"
__all__ = ["DeckError", "parse_layup", "Body", "Box", "Contact", "Cylinder", "Frame", "Grid", "Interface", "Laminate", "Material",
           "Ply", "Run", "Scene", "Sphere", "__version__"]
