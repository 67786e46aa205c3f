"""Truth variants of the virtual TEO: each changes what it says, by the stated amount."""

from __future__ import annotations

import pytest

from zmpkit.errors import ParameterError
from zmpkit.robots.teo.truth import load_truth
from zmpkit.robots.teo.truth_variants import (
    BACKLASH_SCALE,
    PAYLOAD_EXTRA_KG,
    TRUTH_VARIANTS,
    truth_variant,
    write_truth_variants,
)
from zmpkit.sim.spring import SofteningSpring


@pytest.fixture(scope="module")
def variants(tmp_path_factory: pytest.TempPathFactory):
    folder = tmp_path_factory.mktemp("truths")
    paths = write_truth_variants(folder)
    return {p.stem.removeprefix("teo_"): load_truth(p) for p in paths}


def _flex(truth, name):
    return next(f for f in truth.flex if f.name == name)


def _deflection(flex, torque: float) -> float:
    """Deflection [rad] of a flex joint's softening law at ``torque`` [N·m]."""
    spring = SofteningSpring(flex.stiffness[0], flex.softening_torque, flex.softening_torque_range)
    return spring.law_deflection(torque)


@pytest.mark.parametrize(("variant", "scale"), [("stiff_flex", 0.6), ("soft_flex", 1.6)])
def test_compliance_scale_scales_the_deflection_at_every_load(variants, variant, scale) -> None:
    shipped = load_truth()
    for name in ("right_foot_pitch_flex", "left_foot_roll_flex", "right_hip_roll_flex"):
        before, after = _flex(shipped, name), _flex(variants[variant], name)
        for torque in (1.0, 10.0, 40.0):
            ratio = _deflection(after, torque) / _deflection(before, torque)
            assert ratio == pytest.approx(scale, rel=1e-12), (name, torque)
    assert _flex(variants[variant], "trunk_pitch_flex") == _flex(shipped, "trunk_pitch_flex")


def test_backlash_payload_and_offsets(variants) -> None:
    shipped = load_truth()
    assert variants["backlash_x3"].gear.backlash == pytest.approx(
        BACKLASH_SCALE * shipped.gear.backlash
    )
    assert variants["payload_plus3"].payload_mass_kg == pytest.approx(
        shipped.payload_mass_kg + PAYLOAD_EXTRA_KG
    )
    fz = [variants["ft_offsets"].ft_offsets[s][2] for s in ("right", "left")]
    swapped = [-1.5 * shipped.ft_offsets[s][2] for s in ("left", "right")]
    assert fz == pytest.approx(swapped)
    combined = variants["combined"]
    assert combined.gear.backlash == variants["backlash_x3"].gear.backlash
    assert combined.payload_mass_kg == variants["payload_plus3"].payload_mass_kg
    assert combined.ft_offsets == variants["ft_offsets"].ft_offsets
    assert combined.flex == variants["soft_flex"].flex


def test_every_variant_is_written_and_unknown_names_are_refused(variants) -> None:
    assert set(variants) == set(TRUTH_VARIANTS)
    with pytest.raises(ParameterError, match="unknown truth variant 'bogus'; valid: stiff_flex"):
        truth_variant("bogus")
