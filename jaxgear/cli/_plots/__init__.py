"""Every figure the command line writes, as a gear engineer reads it (:mod:`jaxgear.cli.plots`).

The command modules (``run``, ``sweep``, ``_optimise``) compute; the functions here take the
computed data (SI units unless a name says otherwise) and a path, draw one figure and write it
with :func:`savefig` (atomic, PNG, 120 dpi). Figures are built on the Agg canvas directly, so
plotting never changes the process's pyplot backend (a notebook keeps its inline figures). One
module per what they draw: the figure itself (``_figure``), ``jaxgear run``'s quasi-static
curves and maps (``_quasi_static``), the sweep's dynamic factor and pressures (``_sweep``), its
Campbell diagram (``_campbell``), the coupled gearbox's Campbell diagram and housing spectrum
(``_gearbox``), the optimisation's (``_optimisation``), the radiated noise's (``_acoustics``),
the sizing's Pareto fronts (``_sizing``).
"""

from ._acoustics import (
    intensity_map_plot as intensity_map_plot,
    microphone_plot as microphone_plot,
    sound_power_plot as sound_power_plot,
)
from ._campbell import campbell_plot as campbell_plot, harmonic_crossings as harmonic_crossings
from ._figure import (
    DPI as DPI,
    FIGSIZE as FIGSIZE,
    new_figure as new_figure,
    savefig as savefig,
    wrap_titles as wrap_titles,
)
from ._gearbox import (
    coupled_dynamic_factor_plot as coupled_dynamic_factor_plot,
    gearbox_campbell_plot as gearbox_campbell_plot,
    housing_spectrum_plot as housing_spectrum_plot,
)
from ._optimisation import (
    OBJECTIVE_WORDS as OBJECTIVE_WORDS,
    bearing_choice_plot as bearing_choice_plot,
    convergence_plot as convergence_plot,
    convergence_ylabel as convergence_ylabel,
    master_curve_plot as master_curve_plot,
    optimiser_path_plot as optimiser_path_plot,
)
from ._quasi_static import (
    DYNAMIC_ZERO as DYNAMIC_ZERO,
    LUMPED_STIFFNESS_NOTE as LUMPED_STIFFNESS_NOTE,
    SCENE_STIFFNESS_NOTE as SCENE_STIFFNESS_NOTE,
    TE_COINCIDE_SHARE as TE_COINCIDE_SHARE,
    face_map as face_map,
    face_maps as face_maps,
    harris_plot as harris_plot,
    load_map_plot as load_map_plot,
    loaded_path_plot as loaded_path_plot,
    map_difference_plot as map_difference_plot,
    mesh_stiffness_plot as mesh_stiffness_plot,
    root_stress_plot as root_stress_plot,
    te_coincide as te_coincide,
    te_spectrum_plot as te_spectrum_plot,
    train_phasing_plot as train_phasing_plot,
    transmission_error_plot as transmission_error_plot,
)
from ._sweep import (
    FEW_SPEEDS as FEW_SPEEDS,
    PEAK_MIN as PEAK_MIN,
    PEAKS_NAMED as PEAKS_NAMED,
    coincidence_name as coincidence_name,
    coincidences as coincidences,
    dynamic_factor_plot as dynamic_factor_plot,
    mode_number as mode_number,
    name_peaks as name_peaks,
    pressure_speed_plot as pressure_speed_plot,
)
from ._sizing import (
    contact_ratio_plot as contact_ratio_plot,
    pareto_pair_plot as pareto_pair_plot,
    sizing_dynamics_plot as sizing_dynamics_plot,
)
from ._tribology import path_of_contact_plot as path_of_contact_plot
from ._whine import (
    whine_level_plot as whine_level_plot,
    whine_order_plot as whine_order_plot,
    whine_waterfall_plot as whine_waterfall_plot,
)
