# SPDX-License-Identifier: Apache-2.0
"""The bench's STEP-rate figure is the documented steady-state rate of the
step generator model: one step per max(steplen, 1) + max(stepspace, 1) clocks."""

from fractions import Fraction

import pytest

from halfpoint.flows.bench import max_step_rate
from halfpoint.spec.stepgen import StepCfg


@pytest.mark.parametrize("steplen,stepspace", [(1, 1), (1, 0), (0, 0), (2, 3), (24, 24), (5, 1)])
def test_max_step_rate_formula(steplen, stepspace):
    rate = max_step_rate(StepCfg(steplen, stepspace, 0, 0), n=50)
    assert Fraction(rate).limit_denominator(1000) == Fraction(1, max(steplen, 1) + max(stepspace, 1))
