"""``jaxgear run``'s gear whine, for a pair, train or planetary case with ``[whine]``
(:func:`jaxgear.dynamics.whine_response` on the case's lumped dynamic model over the table's
speeds; a planetary stage's :class:`~jaxgear.planetary.PlanetaryModel`: its 2N meshes and the
support forces and torques of its sun, carrier and ring): ``whine/whine.json`` (every order of
every mesh's TE and force and of every bearing force component at every speed, with the
validity flags), ``whine/whine.csv`` (the same, one row per speed and order), the order plots
and the waterfalls of the TE and of the bearing forces (docs/whine.md, "Outputs"); with
``[housing]`` (pair and train), the housing's ERP, named points and operating deflection shapes
from the same response (:mod:`jaxgear.cli._housing_run`). The whine is solved in the library
(:func:`jaxgear.io.case_whine`); this module writes and draws it."""

from __future__ import annotations

import os
from typing import NamedTuple

import numpy as np

from ..io import case_whine, whine_of, write_csv, write_json
from ._bearing_report import bearing_tone_lines
from ._housing_run import housing_outputs, housing_run_line
from ._plots import whine_order_plot, whine_waterfall_plot

__all__ = ["SolvedWhine", "whine_outputs", "whine_run_line"]

#: orders drawn in the order plots (the first, by the model's span: 1, 2, 3, 4 of a pair's mesh)
ORDERS_DRAWN = 4
#: orders drawn in the waterfalls (the higher ones are in whine.csv)
WATERFALL_ORDERS = 8
#: files of the whine/ folder
FILES = ("whine.json", "whine.csv", "te_orders.png", "bearing_orders.png", "te_waterfall.png",
         "bearing_waterfall.png", "support_fixed_frame_waterfall.png")
#: ``nonlinearity`` above which a speed's linear result is flagged as doubtful (docs/whine.md:
#: within about 1 % of the time domain below 0.5 %)
NONLINEAR_LIMIT = 0.02


def _amp_phase(z):
    z = np.asarray(z)
    return np.abs(z), np.degrees(np.angle(z))


class SolvedWhine(NamedTuple):
    """A whine solved elsewhere, for :func:`whine_outputs` to write (a gearbox's,
    :mod:`jaxgear.cli.gearbox`): its ``[whine]`` inputs, the
    :class:`~jaxgear.dynamics.WhineResponse`, each mesh's name and the
    :class:`~jaxgear.io.HousedAcoustics` of its housing placed in it (None: none)."""

    inputs: object
    response: object
    meshes: tuple
    housed: object = None


def whine_outputs(case, out_dir: str, solved: SolvedWhine | None = None) -> dict | None:
    """The whine of ``case`` over its ``[whine]`` speeds into ``out_dir/whine``; None without
    the table. Returns the summary section. ``solved``: the whine already solved (written
    only).

    Raises:
        ValueError: a case whose model is not lumped (condensed bodies, a planetary stage), or
            with coast flanks (one line each).
    """
    inputs = whine_of(case) if solved is None else solved.inputs
    if inputs is None:
        return None
    if solved is None:
        model, housed, w = case_whine(case, inputs)
    else:
        w, housed = solved.response, solved.housed
    folder = os.path.join(out_dir, "whine")
    os.makedirs(folder, exist_ok=True)
    speeds = np.asarray(w.speed, dtype=float)
    f1 = np.asarray(w.frequency, dtype=float)
    orders = np.asarray(w.orders, dtype=float)
    n_meshes = int(w.transmission_error.shape[-1])
    planetary = _planetary_parts(w)  # a planetary stage's meshes, supports and torques
    if planetary is not None:
        mesh_names, names = planetary["meshes"], planetary["bearings"]
    elif solved is not None:  # its own names; no bearing rows (a gearbox's)
        mesh_names, names = list(solved.meshes), []
    else:
        mesh_names = [case.mesh_name(k) for k in range(n_meshes)] if n_meshes > 1 else ["mesh"]
        names = list(getattr(model.scene, "reaction_names", ()))
    te_a, te_p = _amp_phase(w.transmission_error)
    fm_a, fm_p = _amp_phase(w.mesh_force)
    br_a, br_p = _amp_phase(w.bearing_force)
    loss = np.asarray(w.contact_loss, dtype=bool)  # (S, m)
    nonlin = np.asarray(w.nonlinearity, dtype=float)
    invalid = loss.any(axis=1)
    doubtful = (nonlin > NONLINEAR_LIMIT).any(axis=1) & ~invalid
    # whine.csv: one row per speed and order (order 0: the mean)
    S, h = speeds.size, orders.size
    cols = {
        "speed_rad_s": np.repeat(speeds, h),
        "order": np.tile(orders, S),
        "frequency_Hz": (f1[:, None] * orders[None, :]).ravel(),
    }
    for k, n in enumerate(mesh_names):
        cols[f"te_{n}_um"] = te_a[:, :, k].ravel() * 1e6
        cols[f"te_{n}_phase_deg"] = te_p[:, :, k].ravel()
        cols[f"mesh_force_{n}_N"] = fm_a[:, :, k].ravel()
        cols[f"mesh_force_{n}_phase_deg"] = fm_p[:, :, k].ravel()
    for k, n in enumerate(names):
        key = _key(n)
        cols[f"bearing_{key}_N"] = br_a[:, :, k].ravel()
        cols[f"bearing_{key}_phase_deg"] = br_p[:, :, k].ravel()
    for k, n in enumerate(planetary["moments"] if planetary else ()):
        cols[f"support_{_key(n)}_Nm"] = planetary["moment_amp"][:, :, k].ravel()
        cols[f"support_{_key(n)}_phase_deg"] = planetary["moment_phase"][:, :, k].ravel()
    quasi = getattr(w, "order_group", None) is not None  # QuasiPeriodicBalance: each mesh's
    if quasi:
        cols["mesh_frequency_group"] = np.tile(np.asarray(w.order_group, dtype=float), S)
        cols["group_order"] = np.tile(np.asarray(w.group_order, dtype=float), S)
    cols["contact_loss"] = np.repeat(invalid.astype(float), h)
    cols["nonlinearity"] = np.repeat(nonlin.max(axis=1), h)
    write_csv(os.path.join(folder, "whine.csv"), list(cols), list(cols.values()))
    # the order plots and waterfalls (orders 1.. of the span's fundamental)
    drawn = [j for j in range(1, h) if orders[j] == round(orders[j])][:ORDERS_DRAWN] or [1]
    wf = slice(1, 1 + WATERFALL_ORDERS)
    te_total = np.sqrt(np.sum(te_a**2, axis=2))  # (S, h): every mesh's TE, root-sum-square
    title = f"{case.name}: gear whine ({type(inputs.method).__name__}, H = "
    title += f"{inputs.method.harmonics})"
    if getattr(w, "order_group", None) is not None:
        title = title[:-1] + f", S = {inputs.method.sidebands})"
    te_what = "TE" if n_meshes == 1 else f"TE, root-sum-square of the {n_meshes} meshes"
    whine_order_plot(
        os.path.join(folder, "te_orders.png"), speeds, te_total[:, drawn] * 1e6,
        orders[drawn], ylabel=f"{te_what} (µm)", title=title, invalid=invalid,
        note="orders of the first mesh's frequency; one-sided amplitudes",
    )
    whine_waterfall_plot(
        os.path.join(folder, "te_waterfall.png"), speeds, f1, orders[wf],
        te_total[:, wf] * 1e6, label=f"{te_what} (µm)", title=case.name, invalid=invalid,
    )
    if names:
        br_total = np.sqrt(np.sum(br_a**2, axis=2))  # every bearing component, root-sum-square
        b_what = f"bearing force, root-sum-square of the {len(names)} components (N)"
        if planetary is not None:
            b_what = (f"sun, carrier and ring supports (carrier frame), root-sum-square of the "
                      f"{len(names)} components (N)")
        whine_order_plot(
            os.path.join(folder, "bearing_orders.png"), speeds, br_total[:, drawn],
            orders[drawn], ylabel="bearing force (N)", title=title, invalid=invalid,
            note=f"{b_what}; each component in whine.csv",
        )
        whine_waterfall_plot(
            os.path.join(folder, "bearing_waterfall.png"), speeds, f1, orders[wf],
            br_total[:, wf], label="bearing force (N)", title=case.name, invalid=invalid,
            tones=bearing_tone_lines(case),
        )
    if planetary is not None:  # the supports' lines in the fixed frame (a housing's view)
        _fixed_frame_waterfall(folder, case.name, speeds, f1, planetary["section"], invalid)
    files = [f"whine/{n}" for n in FILES if os.path.exists(os.path.join(folder, n))]
    if quasi:  # each mesh's TE at its own frequency's orders
        files += _mesh_order_plots(folder, w, mesh_names, speeds, te_a, title, invalid)
    housing = None if housed is None else housing_outputs(housed, case, w, folder, invalid)
    valid_note = (
        "contact loss at the flagged speeds: the linear (frequency-domain) result does not hold "
        "there; the time domain (jaxgear sweep) is the reference"
        if invalid.any() else "no contact loss over the range"
    )
    section = {
        "method": type(inputs.method).__name__,
        "harmonics": inputs.method.harmonics,
        "positions_per_period": inputs.positions,
        "speeds_rad_s": speeds.tolist(),
        "fundamental_Hz": f1.tolist(),
        "orders": orders.tolist(),
        "meshes": mesh_names,
        "bearing_components": names,
        **({} if not quasi else {
            "order_group": np.asarray(w.order_group).tolist(),
            "group_order": np.asarray(w.group_order).tolist(),
            "mesh_group": list(w.mesh_group),
            "sidebands": inputs.method.sidebands,
            "frame": ("quasi-periodic balance: the meshes run at several mesh frequencies; "
                      "'orders' are each output's frequency over the first mesh's "
                      "(fundamental_Hz), 'order_group' its mesh-frequency group ('mesh_group' "
                      "each mesh's) and 'group_order' its order of that group's frequency"),
        }),
        "transmission_error_m": {"amplitude": te_a.tolist(), "phase_deg": te_p.tolist()},
        "mesh_force_N": {"amplitude": fm_a.tolist(), "phase_deg": fm_p.tolist()},
        "bearing_force_N": {"amplitude": br_a.tolist(), "phase_deg": br_p.tolist()},
        "static_force_N": np.asarray(w.static_force, dtype=float).tolist(),
        "contact_loss": loss.tolist(),
        "nonlinearity": nonlin.tolist(),
        "linear_result_invalid_at_rad_s": speeds[invalid].tolist(),
        "nonlinearity_above_2_percent_at_rad_s": speeds[doubtful].tolist(),
        "validity": valid_note,
        "files": files + ([] if housing is None else housing["files"]),
        **({} if housing is None else {"housing": housing}),
    }
    if planetary is not None:  # the frame of the support forces, the torques
        section |= planetary["section"]
    write_json(os.path.join(folder, "whine.json"), {"case": case.name, **section})
    # the summary keeps the headline, not the arrays
    peak = int(np.argmax(te_total[:, 1])) if h > 1 else 0
    return {
        k: section[k]
        for k in ("method", "harmonics", "positions_per_period", "orders", "validity",
                  "linear_result_invalid_at_rad_s", "nonlinearity_above_2_percent_at_rad_s",
                  "files")
        + (("housing",) if housing is not None else ())
    } | {
        "speed_range_rad_s": [float(speeds[0]), float(speeds[-1])],
        "speeds": int(S),
        "max_te_order_1_um": float(te_total[peak, 1] * 1e6) if h > 1 else 0.0,
        "speed_of_max_te_order_1_rad_s": float(speeds[peak]),
    } | (_largest_mesh(te_a, speeds, mesh_names) if n_meshes > 1 and h > 1 else {})


def _largest_mesh(te_a, speeds, mesh_names) -> dict:
    """The headline of a response of several meshes, beside their root-sum-square: the largest
    order-1 TE of any one mesh over the speeds, the mesh and its speed."""
    one = np.asarray(te_a)[:, 1, :]  # (S, meshes)
    s, k = np.unravel_index(int(np.argmax(one)), one.shape)
    return {
        "te_order_1_is_root_sum_square_of_meshes": len(mesh_names),
        "max_te_order_1_one_mesh_um": float(one[s, k] * 1e6),
        "max_te_order_1_one_mesh": mesh_names[k],
        "speed_of_max_te_order_1_one_mesh_rad_s": float(speeds[s]),
    }


def _mesh_order_plots(folder, w, mesh_names, speeds, te_a, title, invalid) -> list[str]:
    """``te_orders_<mesh>.png``: each mesh's TE at orders 1-4 of its own mesh frequency (a
    :class:`~jaxgear.dynamics.QuasiPeriodicBalance` response); the files written."""
    groups, orders = np.asarray(w.order_group), np.asarray(w.group_order)
    rel = np.asarray(w.orders, dtype=float)
    out = []
    for k, name in enumerate(mesh_names):
        g = w.mesh_group[k]
        pick = [int(np.flatnonzero((groups == g) & (orders == o))[0])
                for o in range(1, ORDERS_DRAWN + 1) if o <= orders.max()]
        path = os.path.join(folder, f"te_orders_{_key(name)}.png")
        whine_order_plot(
            path, speeds, te_a[:, pick, k] * 1e6, orders[pick], ylabel=f"TE of {name} (µm)",
            title=title, invalid=invalid,
            note=(f"orders of {name}'s own mesh frequency ({rel[pick[0]]:.4g} x the first "
                  "mesh's); one-sided amplitudes"),
        )
        out.append(f"whine/te_orders_{_key(name)}.png")
    return out


def _key(name: str) -> str:
    """A component's name as a CSV column key."""
    return name.replace(" ", "_").replace("=", "")


def _planetary_parts(w) -> dict | None:
    """A planetary stage's whine (:class:`~jaxgear.planetary.PlanetaryWhine`): its 2N meshes'
    names, its supports' force components (carrier frame) and its support torques and moments
    (N m) with the JSON keys that say so; None for a pair's or a train's response."""
    if not hasattr(w, "moment_names"):
        return None
    amp, phase = _amp_phase(w.support_moment)
    members, line_f, line_a = w.fixed_frame_lines()
    H = int(w.orders.shape[0]) - 1
    return {
        "meshes": [n.replace(" ", "") for n in w.mesh_names],
        "bearings": list(w.bearing_names),
        "moments": list(w.moment_names),
        "moment_amp": amp,
        "moment_phase": phase,
        "section": {
            "support_moment_components": list(w.moment_names),
            "support_moment_Nm": {"amplitude": amp.tolist(), "phase_deg": phase.tolist()},
            # the in-plane support forces a fixed seat receives: carrier-frame order h at
            # |h f_mesh + f_carrier|, h = -H..H (PlanetaryWhine.fixed_frame_lines)
            "support_fixed_frame": {
                "members": list(members),
                "carrier_frame_order": list(range(-H, H + 1)),
                "frequency_Hz": np.asarray(line_f, dtype=float).tolist(),
                "amplitude_N": np.asarray(line_a, dtype=float).tolist(),
            },
            "frame": (
                "planetary stage: orders of the mesh frequency on the mesh travel; the support "
                "forces (bearing_force_N) along the carrier frame's x, y: a support fixed in "
                "space (the held ring's) sees order h at h f_mesh ± f_carrier "
                "(support_fixed_frame: each line's frequency and x, y amplitude); the torques "
                "about the axis are frame-free; per-tooth deviations ([deviations]) are not in "
                "the whine (the dynamic model's meshes repeat every mesh period)"
            ),
        },
    }


def _fixed_frame_waterfall(folder, name, speeds, f1, section, invalid) -> None:
    """``support_fixed_frame_waterfall.png``: the root-sum-square over the members of each
    fixed-frame line |h f_mesh + f_carrier|, h = −8..8 (at most), as orders of f_mesh (the
    ratio f_carrier / f_mesh is the same at every speed)."""
    ff = section["support_fixed_frame"]
    if not ff["members"]:
        return
    h = np.asarray(ff["carrier_frame_order"])
    keep = np.abs(h) <= WATERFALL_ORDERS
    freq = np.asarray(ff["frequency_Hz"])[:, keep]
    amp = np.sqrt(np.sum(np.asarray(ff["amplitude_N"])[:, keep] ** 2, axis=2))
    orders = freq[0] / f1[0]  # |h + f_carrier / f_mesh|
    # each line by its carrier-frame order and side: "4+" at 4 f_mesh + f_carrier
    labels = [f"{abs(k)}{'+' if k > 0 else '−' if k < 0 else ''}" if k else "f_c"
              for k in h[keep]]
    whine_waterfall_plot(
        os.path.join(folder, "support_fixed_frame_waterfall.png"), speeds, f1, orders, amp,
        label=f"support forces in the fixed frame, root-sum-square of {len(ff['members'])} "
        "members (N)", title=name, invalid=invalid, order_labels=labels,
    )


def whine_run_line(section: dict | None) -> list[str]:
    """What ``jaxgear run`` prints of the ``whine`` section (nothing without one)."""
    if section is None:
        return []
    bad = section["linear_result_invalid_at_rad_s"]
    flag = (f"; contact loss at {len(bad)} speed(s) ({bad[0]:.0f}-{bad[-1]:.0f} rad/s): the "
            "linear result does not hold there" if bad else "; no contact loss")
    lo, hi = section["speed_range_rad_s"]
    n = section.get("te_order_1_is_root_sum_square_of_meshes")
    te = (f"TE order 1 max {section['max_te_order_1_um']:.3g} µm at "
          f"{section['speed_of_max_te_order_1_rad_s']:.0f} rad/s")
    if n:  # several meshes: what is summed, and the largest single mesh
        te = (f"TE order 1, root-sum-square of the {n} meshes, max "
              f"{section['max_te_order_1_um']:.3g} µm at "
              f"{section['speed_of_max_te_order_1_rad_s']:.0f} rad/s; one mesh max "
              f"{section['max_te_order_1_one_mesh_um']:.3g} µm "
              f"({section['max_te_order_1_one_mesh']}, "
              f"{section['speed_of_max_te_order_1_one_mesh_rad_s']:.0f} rad/s)")
    return [
        f"whine ({section['method']}, H = {section['harmonics']}, {section['speeds']} speeds "
        f"{lo:g}-{hi:g} rad/s): {te}{flag} (whine/)"
    ] + housing_run_line(section.get("housing"))
