"""Mobility: degrees of freedom by the Gruebler-Kutzbach count."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

from ..construction import Compiled, Construction, as_compiled
from ..nodes import Polar

__all__ = ["Crank", "Mobility", "cranks", "degrees_of_freedom"]

# -- degrees of freedom -----------------------------------------------------------


@dataclass(frozen=True)
class Mobility:
    """The Gruebler-Kutzbach count of a construction's declared links.

    ``dof = 3 * moving_links - 2 * lower_pairs - higher_pairs``.

    Attributes
    ----------
    moving_links : int
        Declared links that are not the ground, plus one block per slider.
    revolute_joints : int
        At every point shared by k bodies, k - 1 joints.
    prismatic_pairs : int
        One per slider.
    lower_pairs : int
        Revolute joints plus prismatic pairs.
    higher_pairs : int
        Always 0: no node kind makes a higher pair.
    dof : int
    inputs : int
        The number of inputs the construction declares.
    bodies : tuple of str
        The moving bodies (link and slider names); the ground is ``"ground"``.
    joints : dict of str to tuple of str
        For every point joining bodies, the bodies it joins.
    guides : dict of str to str
        For every slider, the body its line belongs to (None if no declared
        body holds both of its points).
    """

    moving_links: int
    revolute_joints: int
    prismatic_pairs: int
    lower_pairs: int
    higher_pairs: int
    dof: int
    inputs: int
    bodies: tuple[str, ...] = ()
    joints: Mapping[str, tuple[str, ...]] = field(default_factory=dict)
    guides: Mapping[str, str | None] = field(default_factory=dict)

    @property
    def matches_inputs(self) -> bool:
        """Return whether the count equals the number of inputs."""
        return self.dof == self.inputs

    def __str__(self) -> str:
        return (f"DOF = 3({self.moving_links}) - 2({self.lower_pairs}) - {self.higher_pairs} "
                f"= {self.dof}; {self.inputs} input{'s' if self.inputs != 1 else ''}"
                f"{'' if self.matches_inputs else ' (mismatch)'}")


def degrees_of_freedom(construction: Construction | Compiled) -> Mobility:
    """Count the degrees of freedom of the declared links and sliders.

    The bodies are the declared links and one block per slider. A link whose
    points are all ground belongs to the ground, and so does every ground point
    (:attr:`~geokin.construction.Compiled.ground`):
    there is one ground body. A point shared by k bodies is k - 1 revolute
    joints. A slider ``Slider(name, point, along=(P, Q))`` is a block pinned
    at ``point`` (one more moving link and one more revolute joint there) and
    sliding on the body that holds P and Q (one prismatic pair). Points in no
    declared link are construction aids and count for nothing.

    Parameters
    ----------
    construction : Construction or Compiled

    Returns
    -------
    Mobility

    Examples
    --------
    >>> from geokin import Construction
    >>> c = Construction("four-bar")
    >>> c.input("theta")
    >>> c.fixed("O2", 0, 0)
    >>> c.fixed("O4", 4, 0)
    >>> c.polar("A", "O2", 1, "theta")
    >>> c.circle_circle("B", ("A", "O4"), (4, 3), branch="left")
    >>> c.link("crank", "O2", "A")
    >>> c.link("coupler", "A", "B")
    >>> c.link("rocker", "B", "O4")
    >>> m = degrees_of_freedom(c)
    >>> print(m)
    DOF = 3(3) - 2(4) - 0 = 1; 1 input
    >>> m.matches_inputs
    True
    """
    compiled = as_compiled(construction)
    fixed = compiled.ground
    members: dict[str, set[str]] = {}
    bodies = []
    for link in compiled.links:
        if all(p in fixed for p in link.points):
            continue
        bodies.append(link.name)
        members[link.name] = set(link.points)
    members["ground"] = set(fixed)
    guides = {}
    for slider in compiled.sliders:
        holders = [b for b in (*bodies, "ground") if set(slider.along) <= members[b]]
        guides[slider.name] = holders[0] if holders else None
        bodies.append(slider.name)
        members[slider.name] = {slider.point}
    joints = {}
    for point in compiled.point_names:
        at = tuple(b for b in ("ground", *bodies) if point in members[b])
        if len(at) > 1:
            joints[point] = at
    revolute = sum(len(at) - 1 for at in joints.values())
    prismatic = len(compiled.sliders)
    lower = revolute + prismatic
    moving = len(bodies)
    return Mobility(moving, revolute, prismatic, lower, 0, 3 * moving - 2 * lower,
                    len(compiled.inputs), tuple(bodies), joints, guides)


@dataclass(frozen=True)
class Crank:
    """A point turned directly by an angle input about another point.

    Attributes
    ----------
    origin, tip : str
        The point it turns about, and the point it places.
    input_name : str
        The angle input that turns it.
    on_link : bool
        Whether a declared link joins ``origin`` and ``tip`` (True where no
        link is declared): a helper point of a construction is no crank.
    grounded : bool
        Whether ``origin`` is a ground point.
    """

    origin: str
    tip: str
    input_name: str
    on_link: bool
    grounded: bool


def cranks(construction: Construction | Compiled) -> tuple[Crank, ...]:
    """Return the cranks of a construction, the likeliest driving crank first.

    A crank is a ``polar`` point without a reference line whose angle uses
    an angle input. Cranks on a declared link come first, then those on a
    ground pivot, then declaration order.

    Examples
    --------
    >>> from geokin import Construction
    >>> c = Construction()
    >>> c.input("theta")
    >>> c.fixed("O", 0, 0)
    >>> c.polar("A", "O", 1, "theta")
    >>> cranks(c)
    (Crank(origin='O', tip='A', input_name='theta', on_link=True, grounded=True),)
    """
    compiled = as_compiled(construction)
    angles = compiled.angle_inputs
    links = [set(link.points) for link in compiled.links]
    found = []
    for step in compiled.steps:
        node = step.node
        if not isinstance(node, Polar) or node.reference is not None:
            continue
        driven = sorted(node.angle.names() & angles)
        if driven:
            on_link = not links or any({node.origin, node.name} <= link for link in links)
            found.append(Crank(node.origin, node.name, driven[0], on_link,
                               node.origin in compiled.ground))
    return tuple(sorted(found, key=lambda c: (not c.on_link, not c.grounded)))
