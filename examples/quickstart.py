"""Quickstart: the accessory spur pair of the seed through the Python API.

Geometry → Weber mesh stiffness → quasi-static transmission error with and without tip relief →
a gradient of TE RMS with respect to the relief depth. Run: ``python examples/quickstart.py``.
"""

import jax

jax.config.update("jax_enable_x64", True)  # float64 for accuracy work (examples switch it on)

import jaxgear as jg  # noqa: E402
import jaxgear.io as jio  # noqa: E402
from jaxgear.cli import run_case  # noqa: E402


def main(out_dir=None):
    case = jio.load_case("accessory-spur")  # Tab. III-1 at 80 N·m, tip relief 15 µm / Γ = 0.25
    pair = case.pair
    print(
        f"ε_α = {pair.transverse_contact_ratio:.4f}, p_bt = {pair.base_pitch * 1e3:.4f} mm, "
        f"a_w = {pair.center_distance * 1e3:.4f} mm"
    )

    mesh = case.mesh_model()  # base-plane cells with Weber–Banaschek stiffness per unit length
    plain = jg.quasi_static(mesh, None, case.torque)  # exact unilateral contact
    relieved = jg.quasi_static(mesh, case.modifications, case.torque)
    print(
        f"TE rms: {plain.te_rms * 1e6:.3f} µm unmodified, {relieved.te_rms * 1e6:.3f} µm with relief"
    )

    def te_rms_um(depth):  # smooth contact: differentiable in the relief depth
        tip = jg.MemberModification(tip_relief_depth=depth, tip_relief_extent=0.25)
        return (
            jg.quasi_static(
                mesh,
                jg.Modifications.symmetric(tip),
                case.torque,
                contact=jg.SmoothContact(case.smooth_width),
            ).te_rms
            * 1e6
        )

    slope = jax.grad(te_rms_um)(15e-6)
    print(f"d(TE rms)/dE at E = 15 µm: {slope * 1e-6:.4f} µm/µm")

    summary = None
    if out_dir is not None:  # the quasi-static files of `jaxgear run` (no speed sweep)
        summary = run_case(case, out_dir, show_progress=False)
    return {"plain": plain, "relieved": relieved, "slope": slope, "summary": summary}


if __name__ == "__main__":
    main("jaxgear-out/quickstart")
