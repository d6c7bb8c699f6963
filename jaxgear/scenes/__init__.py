"""Scenes: the linear structures the contact law acts on, through structure vectors (seed (2.9)).

Quasi-static: :class:`RigidMesh` (both bodies rigid, 1 DOF), :class:`TorsionalPair`,
:class:`Grounded` (pins DOFs of another scene). Dynamic (with a mass matrix):
:class:`TorsionalDynamics`, :class:`RelativeApproach`, :class:`LumpedPair` (rigid 6-DOF gear nodes
on Timoshenko shafts and bearings). Later: condensed FE bodies.
"""

from ._lumped3d import (
    Bearing as Bearing,
)
from ._lumped3d import (
    LumpedPair as LumpedPair,
)
from ._lumped3d import (
    ShaftSpec as ShaftSpec,
)
from ._lumped3d import (
    lumped_pair as lumped_pair,
)
from ._lumped3d import (
    timoshenko_element as timoshenko_element,
)
from ._rigid import RigidMesh as RigidMesh
from ._scene import (
    DynamicScene as DynamicScene,
)
from ._scene import (
    Grounded as Grounded,
)
from ._scene import (
    Scene as Scene,
)
from ._scene import (
    grounded as grounded,
)
from ._torsional import (
    RelativeApproach as RelativeApproach,
)
from ._torsional import (
    TorsionalDynamics as TorsionalDynamics,
)
from ._torsional import (
    TorsionalPair as TorsionalPair,
)
from ._torsional import (
    disc_inertia as disc_inertia,
)
