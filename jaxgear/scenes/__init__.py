"""Scenes: the linear structures the contact law acts on, through structure vectors (seed (2.9)).

Quasi-static: :class:`RigidMesh` (both bodies rigid, 1 DOF), :class:`TorsionalPair`,
:class:`Grounded` (pins DOFs of another scene). Dynamic (with a mass matrix):
:class:`TorsionalDynamics`, :class:`RelativeApproach`, :class:`LumpedPair` (rigid 6-DOF gear nodes
on Timoshenko shafts and bearings). Hybrid: :class:`HybridScene` (the lumped scene with condensed
FE bodies coupled to the cells, seed II-2): a pair (:func:`hybrid_pair`, :class:`HybridPair`) or a
train with flexible gears (:func:`hybrid_train`), its window compliance cacheable per scene
(:func:`cache_window_compliance`).

The 3D scenes hold their gear meshes as a tuple of :class:`GearMesh` (the base-plane mesh model on
its line of action between two gear members); a member is a :class:`RigidMember` (a 6-DOF gear
node, seed (2.9)), a :class:`TorsionalMember` (a gear's rotation alone: the torsional model) or a
:class:`FlexibleMember` (a condensed body through the interface, seed (2.11)–(2.30)). The
torsional model, the lumped 3D and the hybrid scenes are structures with their meshes
(:class:`AssembledScene`). A gear train is one of them with several meshes, described once as a
:class:`TrainSpec` (laid out by :func:`train_layout`) and built from it as each scene kind:
torsional (:meth:`TorsionalTrain.of`, :func:`torsional_train`), lumped 3D
(:meth:`LumpedTrain.of`), hybrid (:meth:`HybridScene.train`); the first two are a
:class:`GearTrain`. :class:`Housing` is a condensed flexible housing the lumped scenes' bearings join the shafts to
(``housing=`` of :func:`lumped_pair` and :meth:`LumpedTrain.of`) instead of the ground; the
band its condensed response holds, cut-off / :data:`HOUSING_BAND`, and the rule a housed
model's frequencies must keep to are the housing's (:func:`housing_band_hz`,
:func:`band_holds`, :func:`band_cutoff_hz`, :func:`band_speed_limit`); a
:class:`HousingMount` is the housing with the joints (:class:`MountJoint`) that seat a
structure's or a model's nodes on it, and their one seat coupling.
:func:`mesh_zone_load` is a unit force spread over a mesh's contact zone
as a load on the structure (zone compliances fᵀ K⁻¹ f).
"""

from ._gear_mesh import (
    GearMesh as GearMesh,
    line_of_action as line_of_action,
    mesh_zone_load as mesh_zone_load,
    pair_mesh as pair_mesh,
)
from ._housing import (
    BAND_RTOL as BAND_RTOL,
    HOUSING_BAND as HOUSING_BAND,
    Housing as Housing,
    band_cutoff_hz as band_cutoff_hz,
    band_holds as band_holds,
    band_speed_limit as band_speed_limit,
    bearing_positions as bearing_positions,
    housing_band_hz as housing_band_hz,
)
from ._hybrid import (
    HybridPair as HybridPair,
    HybridScene as HybridScene,
    cache_window_compliance as cache_window_compliance,
    fit_members as fit_members,
    fit_windows as fit_windows,
    hybrid_pair as hybrid_pair,
    hybrid_train as hybrid_train,
)
from ._interface import (
    FlexibleMember as FlexibleMember,
    GearMember as GearMember,
    GearPlace as GearPlace,
    RigidMember as RigidMember,
    RimStations as RimStations,
    TorsionalMember as TorsionalMember,
    mortar_weights as mortar_weights,
)
from ._mount import (
    ALL_ROWS as ALL_ROWS,
    AXIS_ROWS as AXIS_ROWS,
    HousingMount as HousingMount,
    MountJoint as MountJoint,
)
from ._lumped3d import (
    LumpedPair as LumpedPair,
    LumpedTrain as LumpedTrain,
    Wrench as Wrench,
    lumped_pair as lumped_pair,
    lumped_train as lumped_train,
    mesh_wrench as mesh_wrench,
)
from ._rigid import RigidMesh as RigidMesh
from ._scene import (
    DynamicScene as DynamicScene,
    Grounded as Grounded,
    Scene as Scene,
    grounded as grounded,
    rigid_mode_penalty as rigid_mode_penalty,
)
from ._shaft import (
    Bearing as Bearing,
    Material as Material,
    ShaftMatrices as ShaftMatrices,
    ShaftSpec as ShaftSpec,
    bearing_dofs as bearing_dofs,
    bearing_matrix as bearing_matrix,
    shaft_matrices as shaft_matrices,
    timoshenko_element as timoshenko_element,
)
from ._structure import AssembledScene as AssembledScene, Structure as Structure
from ._torsional import (
    RelativeApproach as RelativeApproach,
    TorsionalDynamics as TorsionalDynamics,
    TorsionalPair as TorsionalPair,
    TorsionalTrain as TorsionalTrain,
    disc_inertia as disc_inertia,
    torsional_train as torsional_train,
)
from ._train import (
    GearTrain as GearTrain,
    TrainLayout as TrainLayout,
    TrainSpec as TrainSpec,
    half_base_angle as half_base_angle,
    mesh_period_ratios as mesh_period_ratios,
    scene_span as scene_span,
    shaft_speeds as shaft_speeds,
    shaft_torques as shaft_torques,
    train_hands as train_hands,
    train_layout as train_layout,
    train_phases as train_phases,
)
from ._window_compliance import (
    WindowCompliance as WindowCompliance,
    window_compliance as window_compliance,
)
