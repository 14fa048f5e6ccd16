"""Linkages described as drawn: links, joints and drivers, compiled into vector loops.

A :class:`Linkage` is given the way a mechanism is sketched: named points with
their coordinates in one assembled pose, the links (rigid bodies) that carry
them, the joints and the driver(s). Every point shared by two or more links is
a revolute joint (a pin joining several links counts once per extra link);
prismatic joints, pin-in-slot half joints, linear actuators (hydraulic
cylinders, collapsed into one variable-length vector) and rolling contacts
without slip (:meth:`Linkage.roll`) are added by name; a rotary motor at a
pin between two moving links (:meth:`Linkage.motor`) drives their relative
angle. Springs and dampers between two points (:meth:`Linkage.spring`) or at
a pin (:meth:`Linkage.torsion_spring`) add no joint: they are known loads in
the force analysis.

The linkage is compiled into the core's vector loops the way the notes teach
(review lecture 3; Norton, *Design of Machinery*, §4.5 and §4.13):

* links are the nodes and joints the edges of the *link graph*; a spanning
  tree grown from the ground gives one independent loop per remaining joint
  (a fundamental cycle basis), so every joint sits on at least one loop;
* in each loop every link contributes the vector from the joint where the loop
  enters it to the joint where it leaves (constant length, angle variable),
  sliders and actuators a variable-length vector;
* vectors of one link that sit in different loops are tied by a
  constant-angle constraint (``theta_b = theta_a + alpha``); links joined by a
  prismatic joint turn together, so they share one angle variable; a link is
  never given three vectors in one loop (no redundancy);
* the drawn pose seeds the Newton–Raphson guesses and selects the circuit: the
  solver marches from the drawn input to the first requested input, so a user
  never types angle guesses.

Angles: ``theta`` of a link is the absolute angle (CCW from +x) of the line
from its first listed point to its second, like θ2, θ3, θ4 of a four-bar; an
angle driver is given in that convention (absolute, radians). Angles are not
wrapped: along a sweep they are continuous.

Newton–Euler force analysis (:meth:`Linkage.forces`) follows the notes' matrix
method (Norton §11.4–11.8): three equations per moving link, the unknown joint
forces ``F_ap`` (force on link *p* from link *a*), prismatic normal forces and
couples, and the driver torque or force, solved for every sample at once.

The package, one room per concept (``docs/linkage.md``, "The package"):

* :mod:`~machdyn.linkage.builder` -- the :class:`Linkage` builder (points,
  links, ground, drivers), its validation and its read-only topology view;
* :mod:`~machdyn.linkage.joints` -- sliders, slots, actuators, rolling
  contacts and motors (the builder methods that add them);
* :mod:`~machdyn.linkage.elements` -- springs and dampers (known loads);
* :mod:`~machdyn.linkage.view` -- the read-only topology view (:class:`Link`,
  :class:`Joint`, :class:`Spring`, :class:`TorsionSpring`);
* :mod:`~machdyn.linkage.topology` -- the link graph, spanning tree and loops;
* :mod:`~machdyn.linkage.groups` -- the Assur-group decomposition
  (:class:`Group`, :attr:`Linkage.groups`), transmission angles, ``flipped``;
* :mod:`~machdyn.linkage.dyads` -- the closed-form dyads, vectorised;
* :mod:`~machdyn.linkage.program`, :mod:`~machdyn.linkage.sweep`,
  :mod:`~machdyn.linkage.kernel` -- the linkage as a program of closed-form
  steps, its solve along a sweep, and the engines that run it (NumPy, the
  compiled kernel :mod:`machdyn._linkage_kernels`, a one-pose twin);
* :mod:`~machdyn.linkage.circuit` -- which samples the drawing reaches (its circuit;
  one driver's range, several drivers' paths);
* :mod:`~machdyn.linkage.loopcompile`, :mod:`~machdyn.linkage.loopsolve` --
  vector-loop compilation for groups the closed forms do not cover, and the
  whole-linkage loop solve (``LinkageMotion.loop_motion``);
* :mod:`~machdyn.linkage.kinematics` -- :meth:`Linkage.solve`'s body and
  :class:`LinkageMotion`;
* :mod:`~machdyn.linkage.forces`, :mod:`~machdyn.linkage.newton_euler` -- the
  Newton–Euler assembler and :class:`LinkageForces`, and its closed-form blocks
  (shared with ``FourBar`` and ``SliderCrank`` dynamics).
"""

from .builder import Linkage
from .forces import FORCE_REASONS, LinkageForces
from .groups import Group
from .kinematics import LinkageMotion
from .view import JOINT_KINDS, Joint, Link, Spring, TorsionSpring

__all__ = [
    "FORCE_REASONS",
    "JOINT_KINDS",
    "Group",
    "Joint",
    "Link",
    "Linkage",
    "LinkageForces",
    "LinkageMotion",
    "Spring",
    "TorsionSpring",
]
