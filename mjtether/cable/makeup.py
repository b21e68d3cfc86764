"""Non-uniform line make-ups: sections of different line types, clump weights, buoyancy modules
and float sections (pure data and NumPy, no MuJoCo).

A ``LineMakeup`` is a list of ``Section`` objects joined end to end from the ship (top) end,
plus point loads (``PointLoad``: a clump weight or a buoyancy module at an arc length) and
distributed buoyancy (``DistributedBuoyancy``: floats spread over a range of arc length). It is
discretised like the uniform ``TetherSpec``: nodes 0 (top) .. N (bottom), every section cut into
its own ``segments`` elements of length ``length / segments``, so each section joint is a node.

* A ``PointLoad`` is split between the two nodes of the element it lies in by the lever rule
  (node k takes 1 - a, node k + 1 takes a, with a the fraction of the element above the load):
  the total and the first moment about any point are kept. A load on a node (a section joint,
  or within 1e-9 of an element length of one) goes wholly to that node.
* A ``DistributedBuoyancy`` is turned into per-element extras: each element gets its overlap with
  the range, per metre of the element, of the floats' volume, mass, drag area and added mass.
  (It is not a set of point loads: a float section acts on every element it covers.)

Per-element arrays (``element_*``) and per-node arrays (``node_*``) are what the solvers use.
``mjtether/cable/linetypes.toml`` holds a small library of named line types with their sources;
``load_line_types()`` reads it and ``Section.from_line_type(name, length, segments)`` uses it.

SI units: m, kg, N; arc lengths are unstretched, from the top end.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields, replace
from functools import cached_property
from importlib.resources import files

import numpy as np
import tomllib

from mjtether import _checks

from mjtether.physics.hydro import DRAG_LAWS

from .tether import (ADDED_MASS, MAX_AXIAL_DAMPING_RATIO, MAX_COEFFICIENT, MAX_LENGTH, MAX_SEGMENTS,
                     MIN_AXIAL_DAMPING_RATIO, TetherSpec)

SNAP = 1e-9
"""A load within this fraction of an element length of a node goes wholly to the node."""


def _name(value, field: str) -> str:
    if not isinstance(value, str):
        raise ValueError(f"{field} must be a string, got {value!r}")
    return value


@dataclass(frozen=True)
class Section:
    """A uniform stretch of line.

    Attributes:
        length: unstretched length (m).
        segments: number of elements of this section (each ``length / segments`` long).
        diameter: hydrodynamic and buoyancy diameter d (m): drag on d l, displaced volume
            pi d^2 / 4 per metre.
        mass_per_length: mass per metre in air (kg/m).
        EA: axial stiffness (N), ``None`` for inextensible.
        EI: bending stiffness (N m^2).
        cd_normal, cd_tangential: drag coefficients (on d l, on pi d l).
        ca_normal: normal added-mass coefficient (on rho pi d^2 / 4 l).
        name: a label (the line type's name for ``from_line_type``).
        mbl: minimum breaking load (N), ``None`` if unknown.
    """

    length: float
    segments: int
    diameter: float
    mass_per_length: float
    EA: float | None = None
    EI: float = 0.0
    cd_normal: float = 1.2
    cd_tangential: float = 0.008
    ca_normal: float = 1.0
    name: str = ""
    mbl: float | None = None

    def __post_init__(self):
        _checks.in_range("section.length", self.length, 1e-3, MAX_LENGTH, "m")
        _checks.positive_int("section.segments", self.segments, 1)
        if self.segments > MAX_SEGMENTS:
            raise ValueError(f"section.segments must be an integer in [1, {MAX_SEGMENTS}], got {self.segments!r}")
        _checks.positive("section.diameter", self.diameter, "m")
        _checks.positive("section.mass_per_length", self.mass_per_length, "kg/m")
        if self.EA is not None:
            _checks.positive("section.EA", self.EA, "N")
        _checks.non_negative("section.EI", self.EI, "N m^2")
        _checks.in_range("section.cd_normal", self.cd_normal, 0.0, MAX_COEFFICIENT)
        _checks.in_range("section.cd_tangential", self.cd_tangential, 0.0, MAX_COEFFICIENT)
        _checks.in_range("section.ca_normal", self.ca_normal, 0.0, MAX_COEFFICIENT)
        _name(self.name, "section.name")
        if self.mbl is not None:
            _checks.positive("section.mbl", self.mbl, "N")

    @property
    def area(self) -> float:
        """Displaced area pi d^2 / 4 (m^2)."""
        return math.pi * self.diameter**2 / 4.0

    @property
    def segment_length(self) -> float:
        """Element length of this section (m)."""
        return self.length / self.segments

    def wet_weight_per_length(self, rho_water: float = 1025.0, gravity: float = 9.81) -> float:
        """Submerged weight per metre (mu - rho A) g (N/m); negative if buoyant."""
        return (self.mass_per_length - rho_water * self.area) * gravity

    @classmethod
    def from_line_type(cls, name: str, length: float, segments: int, **overrides) -> "Section":
        """A section of the named line type of ``load_line_types()``; keyword ``overrides``
        replace any of its properties (e.g. ``cd_normal=1.0``)."""
        types = load_line_types()
        if name not in types:
            raise ValueError(f"unknown line type {name!r}; known: {', '.join(sorted(types))}")
        t = types[name]
        props = dict(diameter=t.diameter, mass_per_length=t.mass_per_length, EA=t.EA, EI=t.EI,
                     cd_normal=t.cd_normal, cd_tangential=t.cd_tangential, ca_normal=t.ca_normal,
                     name=name, mbl=t.mbl)
        unknown = set(overrides) - set(props)
        if unknown:
            raise ValueError(f"Section.from_line_type: unknown override(s) {', '.join(sorted(unknown))}")
        props.update(overrides)
        return cls(length=length, segments=segments, **props)


@dataclass(frozen=True)
class PointLoad:
    """A clump weight (``mass``) and/or buoyancy module (``volume``) at an arc length from the top.

    Attributes:
        arc_length: unstretched distance from the top end (m).
        mass: mass in air (kg).
        volume: displaced volume (m^3); its buoyancy is rho g volume while under water.
        cd_area: drag area C_d A (m^2), isotropic: drag 1/2 rho C_d A |u| u on the node's
            relative velocity u.
        ca: added-mass coefficient on ``volume`` (added mass ca rho volume).
        name: a label.
    """

    arc_length: float
    mass: float = 0.0
    volume: float = 0.0
    cd_area: float = 0.0
    ca: float = 0.0
    name: str = ""

    def __post_init__(self):
        _checks.in_range("point_load.arc_length", self.arc_length, 0.0, MAX_LENGTH, "m")
        _checks.non_negative("point_load.mass", self.mass, "kg")
        _checks.non_negative("point_load.volume", self.volume, "m^3")
        _checks.non_negative("point_load.cd_area", self.cd_area, "m^2")
        _checks.in_range("point_load.ca", self.ca, 0.0, MAX_COEFFICIENT)
        _name(self.name, "point_load.name")

    def wet_weight(self, rho_water: float = 1025.0, gravity: float = 9.81) -> float:
        """Submerged weight (m - rho V) g (N); negative for a net buoyant module."""
        return (self.mass - rho_water * self.volume) * gravity


@dataclass(frozen=True)
class DistributedBuoyancy:
    """Floats spread evenly over arc lengths [start, end] (a float section).

    Attributes:
        start, end: unstretched arc lengths from the top (m), start < end.
        volume_per_length: displaced volume of the floats per metre of line (m^3/m).
        mass_per_length: mass of the floats per metre of line (kg/m).
        cd_area_per_length: normal drag area C_d A of the floats per metre of line (m^2/m),
            added to the line's own normal drag (on the normal relative velocity).
        ca: added-mass coefficient on the floats' volume.
        name: a label.
    """

    start: float
    end: float
    volume_per_length: float
    mass_per_length: float = 0.0
    cd_area_per_length: float = 0.0
    ca: float = 0.0
    name: str = ""

    def __post_init__(self):
        _checks.in_range("distributed_buoyancy.start", self.start, 0.0, MAX_LENGTH, "m")
        _checks.in_range("distributed_buoyancy.end", self.end, 0.0, MAX_LENGTH, "m")
        if not self.end > self.start:
            raise ValueError(f"distributed_buoyancy.end must be > start ({self.start!r} m), got {self.end!r}")
        _checks.non_negative("distributed_buoyancy.volume_per_length", self.volume_per_length, "m^3/m")
        _checks.non_negative("distributed_buoyancy.mass_per_length", self.mass_per_length, "kg/m")
        _checks.non_negative("distributed_buoyancy.cd_area_per_length", self.cd_area_per_length, "m^2/m")
        _checks.in_range("distributed_buoyancy.ca", self.ca, 0.0, MAX_COEFFICIENT)
        _name(self.name, "distributed_buoyancy.name")


def _readonly(a: np.ndarray) -> np.ndarray:
    a.setflags(write=False)
    return a


@dataclass(frozen=True)
class LineMakeup:
    """Sections joined end to end from the top, with point loads and float sections.

    ``sections`` and ``loads`` may be given as any sequences; they are stored as tuples. A uniform
    tether is a one-section make-up without loads (``uniform``, ``is_uniform``); the solvers
    take it as its ``TetherSpec`` (``tether``: the closed-form and scalar paths, payout).

    The dynamic model's properties of the whole line (as ``TetherSpec``'s):
        axial_damping_ratio: damping ratio of one element's axial mode, in
            [MIN_AXIAL_DAMPING_RATIO, MAX_AXIAL_DAMPING_RATIO] (see ``TetherSpec``).
        added_mass: ``"isotropic"`` or ``"normal"``: the default of ``builder.add_tether``.
        drag_law: ``"morison"``, or for a uniform line ``"loading_functions"`` (see
            ``TetherSpec``; the per-section coefficients of a make-up take Morison's).

    (A rated load is not the line's: a scenario's ``tether.rated_load`` stays with the scenario;
    a section's ``mbl`` is its line type's.)
    """

    sections: tuple
    loads: tuple = ()
    axial_damping_ratio: float = 1.0
    added_mass: str = "isotropic"
    drag_law: str = "morison"

    def __post_init__(self):
        try:
            sections = tuple(self.sections)
            loads = tuple(self.loads)
        except TypeError:
            raise ValueError("line_makeup.sections and line_makeup.loads must be sequences") from None
        if not sections:
            raise ValueError("line_makeup.sections must hold at least one Section")
        for i, s in enumerate(sections):
            if not isinstance(s, Section):
                raise ValueError(f"line_makeup.sections[{i}] must be a Section, got {type(s).__name__}")
        n = sum(s.segments for s in sections)
        if n > MAX_SEGMENTS:
            raise ValueError(f"line_makeup: {n} elements in all; at most {MAX_SEGMENTS}")
        L = math.fsum(s.length for s in sections)
        for i, p in enumerate(loads):
            if isinstance(p, PointLoad):
                if p.arc_length > L * (1 + 1e-12):
                    raise ValueError(f"line_makeup.loads[{i}].arc_length must be in [0, {L:.6g}] m (the line's "
                                     f"length), got {p.arc_length!r}")
            elif isinstance(p, DistributedBuoyancy):
                if p.end > L * (1 + 1e-12):
                    raise ValueError(f"line_makeup.loads[{i}].end must be <= {L:.6g} m (the line's length), "
                                     f"got {p.end!r}")
            else:
                raise ValueError(f"line_makeup.loads[{i}] must be a PointLoad or DistributedBuoyancy, "
                                 f"got {type(p).__name__}")
        object.__setattr__(self, "sections", sections)
        object.__setattr__(self, "loads", loads)
        zeta = _checks.finite("line_makeup.axial_damping_ratio", self.axial_damping_ratio)
        if not MIN_AXIAL_DAMPING_RATIO <= zeta <= MAX_AXIAL_DAMPING_RATIO:
            raise ValueError(f"line_makeup.axial_damping_ratio must be in [{MIN_AXIAL_DAMPING_RATIO}, "
                             f"{MAX_AXIAL_DAMPING_RATIO}] (fraction of critical), got {self.axial_damping_ratio!r}")
        if self.added_mass not in ADDED_MASS:
            raise ValueError(f"line_makeup.added_mass must be one of {', '.join(ADDED_MASS)}, got {self.added_mass!r}")
        if self.drag_law not in DRAG_LAWS:
            raise ValueError(f"line_makeup.drag_law must be one of {', '.join(DRAG_LAWS)}, got {self.drag_law!r}")
        if self.drag_law != "morison" and not self.is_uniform:
            raise ValueError(f"line_makeup.drag_law = {self.drag_law!r} is for a uniform line (one section, no loads); "
                             "a make-up of several sections or with loads takes 'morison'")

    # ------------------------------------------------------------------ construction

    @classmethod
    def uniform(cls, tether: TetherSpec) -> "LineMakeup":
        """The one-section make-up of a uniform ``TetherSpec``, with its axial damping ratio,
        added-mass mode and drag law (``tether`` gives it back, the same numbers)."""
        if not isinstance(tether, TetherSpec):
            raise ValueError(f"tether must be a TetherSpec, got {type(tether).__name__}")
        line = cls((Section(tether.length, tether.segments, tether.diameter, tether.mu, EA=tether.EA,
                            EI=tether.EI, cd_normal=tether.cd_normal, cd_tangential=tether.cd_tangential,
                            ca_normal=tether.ca_normal),))
        # (the TetherSpec's own, which it has checked; not again: tests/cable/test_axial_damping_bound.py
        # bypasses that check to show what goes wrong below the range)
        for name in ("axial_damping_ratio", "added_mass", "drag_law"):
            object.__setattr__(line, name, getattr(tether, name))
        return line

    @classmethod
    def of(cls, tether, field: str = "tether") -> "LineMakeup":
        """``tether`` as a make-up: a ``LineMakeup`` as it is, a ``TetherSpec`` as its one section
        (``uniform``); ValueError naming ``field`` for anything else."""
        if isinstance(tether, LineMakeup):
            return tether
        if isinstance(tether, TetherSpec):
            return cls.uniform(tether)
        raise ValueError(f"{field} must be a TetherSpec or a LineMakeup, got {type(tether).__name__}")

    @cached_property
    def tether(self) -> TetherSpec:
        """The uniform ``TetherSpec`` this line is (one section, no loads: ``is_uniform``): its
        section's length, elements, diameter, mass per metre, EA, EI and coefficients, with the
        make-up's axial damping ratio, added-mass mode and drag law. The same numbers as the
        ``TetherSpec`` that ``uniform`` was given (its ``mu`` as ``mass_per_length``). ValueError
        for a line of several sections or with loads, which no ``TetherSpec`` describes."""
        if not self.is_uniform:
            raise ValueError(f"line_makeup: {len(self.sections)} section(s) and {len(self.loads)} load(s) make no "
                             "uniform tether (one section, no loads)")
        s = self.sections[0]
        return TetherSpec(length=s.length, segments=s.segments, diameter=s.diameter, mass_per_length=s.mass_per_length,
                          cd_normal=s.cd_normal, cd_tangential=s.cd_tangential, ca_normal=s.ca_normal, EA=s.EA,
                          EI=s.EI, axial_damping_ratio=self.axial_damping_ratio, added_mass=self.added_mass,
                          drag_law=self.drag_law)

    def reversed(self) -> "LineMakeup":
        """The same line numbered from the other end (sections in reverse order, arc lengths
        mirrored)."""
        L = self.length
        loads = []
        for p in self.loads:
            if isinstance(p, PointLoad):
                loads.append(PointLoad(max(L - p.arc_length, 0.0), p.mass, p.volume, p.cd_area, p.ca, p.name))
            else:
                loads.append(DistributedBuoyancy(max(L - p.end, 0.0), L - p.start, p.volume_per_length,
                                                 p.mass_per_length, p.cd_area_per_length, p.ca, p.name))
        return replace(self, sections=self.sections[::-1], loads=tuple(loads))

    def truncated(self, length: float) -> "LineMakeup":
        """The top ``length`` m of the line (e.g. all but the part rising to a walker's tow
        point): the sections up to there, the last one cut with its element length kept as near
        as a whole number of elements allows (at least one). Point loads and floats must lie
        within the kept part (ValueError otherwise: where the line was cut they would have no
        place)."""
        L = self.length
        length = _checks.in_range("line_makeup.truncated length", length, 1e-3, L, "m")
        if length >= L * (1 - 1e-12):
            return self
        for p in self.loads:
            end = p.arc_length if isinstance(p, PointLoad) else p.end
            if end > length + 1e-9 * L:
                what = f"point load {p.name!r} at {p.arc_length:g} m" if isinstance(p, PointLoad) else \
                    f"floats {p.name!r} up to {p.end:g} m"
                raise ValueError(f"line_makeup: the {what} lies in the last {L - length:.3g} m of the line, which "
                                 "is cut off here (it rises straight to the tow point); move it up the line")
        sections = []
        for sec, (a, b) in zip(self.sections, zip(self.section_bounds[:-1], self.section_bounds[1:])):
            if a >= length:
                break
            if b <= length:
                sections.append(sec)
                continue
            keep = length - a
            sections.append(replace(sec, length=keep, segments=max(1, round(keep / sec.segment_length))))
        return replace(self, sections=tuple(sections))

    # ------------------------------------------------------------------ geometry

    @property
    def length(self) -> float:
        """Total unstretched length (m)."""
        return float(self.section_bounds[-1])

    total_length = length

    @property
    def segments(self) -> int:
        """Total number of elements N."""
        return sum(s.segments for s in self.sections)

    @property
    def is_uniform(self) -> bool:
        """One section and no loads: the same as a ``TetherSpec`` (``tether``)."""
        return len(self.sections) == 1 and not self.loads

    @property
    def pays_out(self) -> bool:
        """Whether a winch may pay this line out and reel it in: a uniform one, whose drum pays
        out more of its one section (``builder.add_tether``'s ``max_length``; ``drum`` lumps its
        one mass per metre). A make-up's sections and loads have fixed places on it: its length
        is fixed."""
        return self.is_uniform

    @cached_property
    def section_bounds(self) -> np.ndarray:
        """Arc lengths (m) of the section ends, shape (K+1,): 0, joints, total length."""
        return _readonly(np.concatenate([[0.0], np.cumsum([s.length for s in self.sections])]))

    @cached_property
    def section_nodes(self) -> np.ndarray:
        """Node index of each section end, shape (K+1,)."""
        return _readonly(np.concatenate([[0], np.cumsum([s.segments for s in self.sections])]).astype(int))

    @cached_property
    def element_section(self) -> np.ndarray:
        """Index of the section of each element, shape (N,)."""
        return _readonly(np.repeat(np.arange(len(self.sections)), [s.segments for s in self.sections]))

    def _per_element(self, attr) -> np.ndarray:
        return np.array([attr(s) for s in self.sections], dtype=float)[self.element_section]

    @cached_property
    def element_length(self) -> np.ndarray:
        """Unstretched element lengths (m), shape (N,): each section's length / segments."""
        return _readonly(self._per_element(lambda s: s.length / s.segments))

    @cached_property
    def node_arc_length(self) -> np.ndarray:
        """Unstretched arc length of each node from the top (m), shape (N+1,); the section
        joints are exact (not sums of element lengths)."""
        s = np.empty(self.segments + 1)
        for k, sec in enumerate(self.sections):
            a, b = self.section_nodes[k], self.section_nodes[k + 1]
            s[a:b] = self.section_bounds[k] + np.arange(sec.segments) * (sec.length / sec.segments)
        s[-1] = self.section_bounds[-1]
        return _readonly(s)

    # ------------------------------------------------------------------ element properties

    @cached_property
    def _floats(self) -> np.ndarray:
        """Per-element extras of the distributed buoyancy, per metre: (volume, mass, cd_area,
        ca * volume), shape (4, N)."""
        out = np.zeros((4, self.segments))
        s0, s1 = self.node_arc_length[:-1], self.node_arc_length[1:]
        for p in self.loads:
            if isinstance(p, DistributedBuoyancy):
                frac = np.clip(np.minimum(s1, p.end) - np.maximum(s0, p.start), 0.0, None) / (s1 - s0)
                out += np.outer([p.volume_per_length, p.mass_per_length, p.cd_area_per_length,
                                 p.ca * p.volume_per_length], frac)
        return _readonly(out)

    @cached_property
    def element_diameter(self) -> np.ndarray:
        """The line's hydrodynamic diameter d of each element (m), shape (N,)."""
        return _readonly(self._per_element(lambda s: s.diameter))

    @cached_property
    def element_area(self) -> np.ndarray:
        """Displaced volume per metre of each element (m^2): pi d^2 / 4 plus the floats'."""
        return _readonly(self._per_element(lambda s: s.area) + self._floats[0])

    @cached_property
    def element_mass_per_length(self) -> np.ndarray:
        """Mass per metre in air of each element (kg/m), floats included."""
        return _readonly(self._per_element(lambda s: s.mass_per_length) + self._floats[1])

    @cached_property
    def element_EA(self) -> np.ndarray:
        """Axial stiffness of each element (N); ``inf`` where inextensible."""
        return _readonly(self._per_element(lambda s: math.inf if s.EA is None else s.EA))

    @cached_property
    def element_EI(self) -> np.ndarray:
        """Bending stiffness of each element (N m^2)."""
        return _readonly(self._per_element(lambda s: s.EI))

    @cached_property
    def element_cd_normal(self) -> np.ndarray:
        return _readonly(self._per_element(lambda s: s.cd_normal))

    @cached_property
    def element_cd_tangential(self) -> np.ndarray:
        return _readonly(self._per_element(lambda s: s.cd_tangential))

    @cached_property
    def element_ca_normal(self) -> np.ndarray:
        """The line's own normal added-mass coefficient of each element."""
        return _readonly(self._per_element(lambda s: s.ca_normal))

    @cached_property
    def element_float_cd_area(self) -> np.ndarray:
        """Normal drag area C_d A of the floats per metre of each element (m^2/m)."""
        return _readonly(self._floats[2].copy())

    @cached_property
    def element_float_added_volume(self) -> np.ndarray:
        """ca * volume of the floats per metre of each element (m^2): their added mass per
        metre is rho times this."""
        return _readonly(self._floats[3].copy())

    def element_wet_weight(self, rho_water: float = 1025.0, gravity: float = 9.81) -> np.ndarray:
        """Submerged weight per metre of each element (N/m), floats included; negative where
        buoyant."""
        return (self.element_mass_per_length - rho_water * self.element_area) * gravity

    # ------------------------------------------------------------------ node extras

    @cached_property
    def _nodes(self) -> np.ndarray:
        """Point loads lumped on the nodes by the lever rule: (mass, volume, cd_area,
        ca * volume), shape (4, N+1)."""
        out = np.zeros((4, self.segments + 1))
        s = self.node_arc_length
        N = self.segments
        for p in self.loads:
            if not isinstance(p, PointLoad):
                continue
            q = np.array([p.mass, p.volume, p.cd_area, p.ca * p.volume])
            k = int(np.clip(np.searchsorted(s, p.arc_length, side="right") - 1, 0, N - 1))
            a = (p.arc_length - s[k]) / (s[k + 1] - s[k])
            if a <= SNAP:
                out[:, k] += q
            elif a >= 1.0 - SNAP:
                out[:, k + 1] += q
            else:
                out[:, k] += (1.0 - a) * q
                out[:, k + 1] += a * q
        return _readonly(out)

    @cached_property
    def node_mass(self) -> np.ndarray:
        """Lumped point-load mass on each node (kg), shape (N+1,)."""
        return _readonly(self._nodes[0].copy())

    @cached_property
    def node_volume(self) -> np.ndarray:
        """Lumped point-load volume on each node (m^3)."""
        return _readonly(self._nodes[1].copy())

    @cached_property
    def node_cd_area(self) -> np.ndarray:
        """Lumped point-load drag area C_d A on each node (m^2)."""
        return _readonly(self._nodes[2].copy())

    @cached_property
    def node_added_volume(self) -> np.ndarray:
        """Lumped ca * volume on each node (m^3): the node's extra added mass is rho times this."""
        return _readonly(self._nodes[3].copy())

    @cached_property
    def node_ca(self) -> np.ndarray:
        """Volume-weighted added-mass coefficient of the point loads on each node (0 where none)."""
        v = self._nodes[1]
        return _readonly(np.divide(self._nodes[3], v, out=np.zeros_like(v), where=v > 0))

    @property
    def has_point_loads(self) -> bool:
        return any(isinstance(p, PointLoad) for p in self.loads)

    @property
    def has_floats(self) -> bool:
        """Any distributed buoyancy (float sections): the elements' displaced area is then not
        the line's own pi d^2 / 4 alone."""
        return any(isinstance(p, DistributedBuoyancy) for p in self.loads)

    def node_wet_weight(self, rho_water: float = 1025.0, gravity: float = 9.81) -> np.ndarray:
        """Submerged weight of the point loads on each node (N); negative where buoyant."""
        return (self.node_mass - rho_water * self.node_volume) * gravity


# ---------------------------------------------------------------------- line-type library


@dataclass(frozen=True)
class LineType:
    """A named line type of the library (SI units; see ``mjtether/cable/linetypes.toml``)."""

    name: str
    diameter: float
    mass_per_length: float
    EA: float | None
    EI: float
    cd_normal: float
    cd_tangential: float
    ca_normal: float
    mbl: float
    source: str
    description: str = ""

    def wet_weight_per_length(self, rho_water: float = 1025.0, gravity: float = 9.81) -> float:
        """Submerged weight per metre (N/m); negative if buoyant."""
        return (self.mass_per_length - rho_water * math.pi * self.diameter**2 / 4.0) * gravity


_REQUIRED = ("diameter", "mass_per_length", "EA", "EI", "cd_normal", "cd_tangential", "ca_normal", "mbl", "source")


def _parse_line_types(tree: dict, where: str) -> dict[str, LineType]:
    types = {}
    known = {f.name for f in fields(LineType)} - {"name"}
    for name, entry in tree.items():
        if not isinstance(entry, dict):
            raise ValueError(f"{where}: [{name}] must be a table")
        missing = [k for k in _REQUIRED if k not in entry]
        if missing:
            raise ValueError(f"{where}: [{name}] lacks {', '.join(missing)}")
        unknown = set(entry) - known
        if unknown:
            raise ValueError(f"{where}: [{name}] has unknown key(s) {', '.join(sorted(unknown))}")
        lt = LineType(name=name, **entry)
        # the same checks as a Section (a one-metre one), naming the type
        try:
            Section(1.0, 1, lt.diameter, lt.mass_per_length, EA=lt.EA, EI=lt.EI, cd_normal=lt.cd_normal,
                    cd_tangential=lt.cd_tangential, ca_normal=lt.ca_normal, name=name, mbl=lt.mbl)
        except ValueError as exc:
            raise ValueError(f"{where}: [{name}]: {exc}") from None
        if not isinstance(lt.source, str) or not lt.source.strip():
            raise ValueError(f"{where}: [{name}].source must be a non-empty string")
        types[name] = lt
    return types


def load_line_types(path=None) -> dict[str, LineType]:
    """The line-type library: ``mjtether/cable/linetypes.toml`` (or the TOML file ``path``), as
    {name: LineType}."""
    if path is None:
        text = (files("mjtether.cable") / "linetypes.toml").read_text(encoding="utf-8")
        where = "linetypes.toml"
    else:
        with open(path, encoding="utf-8") as f:
            text = f.read()
        where = str(path)
    try:
        tree = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ValueError(f"{where}: {exc}") from None
    return _parse_line_types(tree, where)


__all__ = ["DistributedBuoyancy", "LineMakeup", "LineType", "PointLoad", "Section", "load_line_types"]
