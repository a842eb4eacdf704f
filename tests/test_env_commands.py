"""The environment given random commands, every answer as a twin's.

A single environment against its twin carried through copies and pickles of itself and of
its states (clone_state, restore_state): a copy plays on as the original would. The
native batch on worker processes against the same batch in one process: the workers'
protocol has a message of its own for each command (by pipe, after a go), and sends
spilled events and a call's results after its answer; none may be left over for the next
command, whatever the order of commands."""

from __future__ import annotations

import copy
import pickle
from typing import ClassVar

import gymnasium
import numpy as np
from hypothesis import settings
from hypothesis import strategies as st
from hypothesis.stateful import RuleBasedStateMachine, initialize, precondition, rule

import invaders.env  # noqa: F401  (registers the id)
from invaders.env.space_invaders import SpaceInvadersEnv
from tests.helpers import vector_answers_alike

ENV_ID = "invaders/SpaceInvaders-v0"
# Steps of up to 1,500 frames (drawn by each game's generator), so that many steps have
# more events than a game's row keeps (spilled: 4 to 15 game steps in 4 to 19 steps of
# the examples that step, counted once) and episodes end, by the limit and at game over
# (autoreset at the next step).
OPTIONS = {"obs_type": "state", "frameskip": (1, 1500), "max_num_frames_per_episode": 6000}
ACTIONS = st.lists(st.integers(0, 5), min_size=3, max_size=3)
MASKS = st.lists(st.booleans(), min_size=3, max_size=3).filter(any)


SEEDS = st.integers(0, 2**16)


class CopiesAlike(RuleBasedStateMachine):
    """An environment (grey, shrunk and stacked, frame skips drawn) and its twin: the twin
    is now and then replaced by its copy or by its pickle loaded, and restores states
    pickled and loaded where the environment restores its own."""

    def __init__(self) -> None:
        super().__init__()
        options = {"obs_type": "grayscale", "resize": (84, 84), "stack": 2,
                   "frameskip": (2, 8), "max_num_frames_per_episode": 1500}
        self.env, self.twin = SpaceInvadersEnv(**options), SpaceInvadersEnv(**options)
        self.states: tuple | None = None

    @initialize(seed=SEEDS)
    def reset(self, seed):
        self._alike([env.reset(seed=seed) for env in (self.env, self.twin)])

    @rule(seed=st.none() | SEEDS)
    def reset_again(self, seed):
        self._alike([env.reset(seed=seed) for env in (self.env, self.twin)])

    @rule(actions=st.lists(st.integers(0, 5), min_size=1, max_size=20))
    def step(self, actions):
        for action in actions:
            self._alike([env.step(action) for env in (self.env, self.twin)])

    @rule(include_rng=st.booleans())
    def clone(self, include_rng):
        self.states = (self.env.clone_state(include_rng),
                       pickle.dumps(self.twin.clone_state(include_rng)))

    @precondition(lambda self: self.states is not None)
    @rule()
    def restore(self):
        assert self.states is not None
        self.env.restore_state(self.states[0])
        self.twin.restore_state(pickle.loads(self.states[1]))

    @rule()
    def copy_twin(self):
        self.twin = copy.deepcopy(self.twin)

    @rule()
    def pickle_twin(self):
        self.twin = pickle.loads(pickle.dumps(self.twin))

    def _alike(self, answers: list[tuple]) -> None:
        for one, other in zip(*answers, strict=True):
            assert np.array_equal(one, other) if isinstance(one, np.ndarray) else one == other

    def teardown(self) -> None:
        self.env.close()
        self.twin.close()


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

    @initialize(seed=SEEDS)
    def reset(self, seed):
        self._alike([venv.reset(seed=seed) for venv in (self.here, self.apart)])

    @rule(actions=ACTIONS)
    def step(self, actions):
        self._alike([venv.step(np.array(actions)) for venv in (self.here, self.apart)])

    @rule(seed=SEEDS, mask=MASKS)
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
        assert vector_answers_alike(*answers)

    def teardown(self) -> None:
        self.here.close()
        self.apart.close()


class SameStepBatchesAlike(BatchesAlike):
    """The same, an ended game reset within its step (a partial reset of the games, on
    workers too, inside a step)."""

    options: ClassVar[dict] = {**OPTIONS, "autoreset_mode": "SameStep"}


# (60 examples of the single environment, which are cheap: fewer, derandomized, missed a
# pickle that forgot the last input sticky actions repeat)
for machine, examples in ((CopiesAlike, 60), (BatchesAlike, 25), (SameStepBatchesAlike, 25)):
    machine.TestCase.settings = settings(max_examples=examples, stateful_step_count=20,
                                         deadline=None)
test_an_environment_plays_on_alike_through_copies_of_itself_and_its_states = (
    CopiesAlike.TestCase)
test_the_batch_on_workers_answers_random_commands_as_in_one_process = BatchesAlike.TestCase
test_so_does_one_resetting_within_the_step = SameStepBatchesAlike.TestCase
