"""The native batch on worker processes given random commands: every answer as the same
batch's in one process. The workers' protocol has a message of its own for each command
(by pipe, after a go), and sends spilled events and a call's results after its answer;
none may be left over for the next command, whatever the order of commands."""

from __future__ import annotations

from typing import ClassVar

import gymnasium
import numpy as np
from hypothesis import settings
from hypothesis import strategies as st
from hypothesis.stateful import RuleBasedStateMachine, initialize, rule

import invaders.env  # noqa: F401  (registers the id)
from tests.helpers import infos_alike

ENV_ID = "invaders/SpaceInvaders-v0"
# Steps of up to 1,500 frames (drawn by each game's generator), so that many steps have
# more events than a game's row keeps (spilled: 4 to 15 game steps in 4 to 19 steps of
# the examples that step, counted once) and episodes end, by the limit and at game over
# (autoreset at the next step).
OPTIONS = {"obs_type": "state", "frameskip": (1, 1500), "max_num_frames_per_episode": 6000}
ACTIONS = st.lists(st.integers(0, 5), min_size=3, max_size=3)
MASKS = st.lists(st.booleans(), min_size=3, max_size=3).filter(any)


class BatchesAlike(RuleBasedStateMachine):
    """Three games on two workers (the caller's share of two, a worker's of one) against
    the same three in one process."""

    options: ClassVar[dict] = OPTIONS

    def __init__(self) -> None:
        super().__init__()
        self.here = gymnasium.make_vec(ENV_ID, num_envs=3,
                                       vectorization_mode="vector_entry_point", **self.options)
        self.apart = gymnasium.make_vec(ENV_ID, num_envs=3, workers=2,
                                        vectorization_mode="vector_entry_point", **self.options)

    @initialize(seed=st.integers(0, 2**16))
    def reset(self, seed):
        self._alike([venv.reset(seed=seed) for venv in (self.here, self.apart)])

    @rule(actions=ACTIONS)
    def step(self, actions):
        self._alike([venv.step(np.array(actions)) for venv in (self.here, self.apart)])

    @rule(seed=st.integers(0, 2**16), mask=MASKS)
    def reset_some(self, seed, mask):
        options = {"reset_mask": np.array(mask)}
        self._alike([venv.reset(seed=seed, options=options) for venv in (self.here, self.apart)])

    @rule(values=st.lists(st.integers(), min_size=3, max_size=3) | st.integers())
    def set_then_get(self, values):
        for venv in (self.here, self.apart):
            venv.set_attr("tag", values)
        tags = tuple(values) if isinstance(values, list) else (values,) * 3
        assert self.here.get_attr("tag") == self.apart.get_attr("tag") == tags

    @rule()
    def call(self):
        states = [[state.world.state_hash() for state in venv.call("clone_state")]
                  for venv in (self.here, self.apart)]
        assert states[0] == states[1]

    def _alike(self, answers: list[tuple]) -> None:
        """Each part of the two answers equal: arrays, and infos as Gymnasium merges them."""
        for one, other in zip(*answers, strict=True):
            assert infos_alike(one, other) if isinstance(one, dict) else np.array_equal(
                one, other)

    def teardown(self) -> None:
        self.here.close()
        self.apart.close()


class SameStepBatchesAlike(BatchesAlike):
    """The same, an ended game reset within its step (a partial reset of the games, on
    workers too, inside a step)."""

    options: ClassVar[dict] = {**OPTIONS, "autoreset_mode": "SameStep"}


for machine in (BatchesAlike, SameStepBatchesAlike):
    machine.TestCase.settings = settings(max_examples=25, stateful_step_count=20,
                                         deadline=None)
test_the_batch_on_workers_answers_random_commands_as_in_one_process = BatchesAlike.TestCase
test_so_does_one_resetting_within_the_step = SameStepBatchesAlike.TestCase
