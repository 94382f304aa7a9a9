"""Family models (SPEC 16): one network, fitted on many members of a family of shapes, meshes
a new member in a forward pass (docs/family.md).

``members`` (a member's exact boundary nodes and base grid, by kind), ``encoding`` (its
boundary nodes reduced by the family's principal components), ``physics`` (the Winslow
equations linearised at a grid: one solve), ``network`` (the correction's network, NumPy's
forward pass), ``train`` (its training, torch), ``model`` (fit, predict, save, load) and
``mesh`` (a member's grid with the guard and its report)."""

from pinn_engine.family.members import Member, blocks_member, member_of, refuse_blocks_options
from pinn_engine.family.mesh import BlocksStart, family_size, mesh_member
from pinn_engine.family.model import FamilyModel, load_family

__all__ = [
    "BlocksStart",
    "FamilyModel",
    "Member",
    "blocks_member",
    "family_size",
    "load_family",
    "member_of",
    "mesh_member",
    "refuse_blocks_options",
]
