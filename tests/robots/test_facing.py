"""The evidence on which way a model faces (:mod:`zmpkit.robots.facing`)."""

from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st

from zmpkit.robots.facing import FacingVote, decide, side_from_names


@pytest.mark.parametrize(
    ("names", "side"),
    [
        (["leg_left_6_link", "leg_left_4_joint"], "left"),  # TALOS
        (["l_foot_link", "l_knee_fe"], "left"),  # Apollo
        (["LAnklePitch", "LKneePitch"], "left"),  # NAO
        (["Right_Knee_Pitch", "right_foot_link"], "right"),  # Booster T1
        (["r_ank_roll"], "right"),  # OP3
        (["ll_faa", "ll_kfe"], None),  # Berkeley Humanoid: "ll" is not a side
        (["left_hip", "right_foot"], None),  # contradicting
        (["pelvis", "shank"], None),
        (["leftover_link"], None),  # a token, not a substring
    ],
)
def test_side_from_names(names: list[str], side: str | None) -> None:
    assert side_from_names(names) == side


def _vote(source: str, sign: int, strong: bool) -> FacingVote:
    return FacingVote(source, sign, strong, "")


@pytest.mark.parametrize(
    ("signs", "expected"),
    [
        ((1, 1, 1), (1, True)),
        ((1, 1, -1), (1, True)),  # two strong outweigh the weak toes (TALOS)
        ((1, 0, -1), (1, False)),  # one strong against the toes: check by hand
        ((0, -1, -1), (-1, True)),  # no names: the knees decide (Berkeley Humanoid)
        ((1, -1, 1), (1, False)),  # names against knees
        ((0, 0, -1), (-1, False)),  # the weak toes alone
        ((0, 0, 0), (1, False)),
    ],
)
def test_decide(signs: tuple[int, int, int], expected: tuple[int, bool]) -> None:
    votes = [_vote("names", signs[0], True), _vote("knees", signs[1], True)]
    assert decide([*votes, _vote("toes", signs[2], False)]) == expected


@given(
    st.lists(st.tuples(st.sampled_from([-1, 0, 1]), st.booleans()), min_size=1, max_size=4).filter(
        lambda votes: any(sign for sign, _ in votes)
    )
)
def test_decide_turns_with_the_model(votes: list[tuple[int, bool]]) -> None:
    """Turning the model half a turn flips every vote and so the guess, never its sureness."""
    ahead = [_vote(str(i), sign, strong) for i, (sign, strong) in enumerate(votes)]
    behind = [_vote(str(i), -sign, strong) for i, (sign, strong) in enumerate(votes)]
    sign, sure = decide(ahead)
    assert decide(behind) == (-sign, sure)
