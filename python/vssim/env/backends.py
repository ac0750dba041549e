"""The worlds under an environment, seen as batches: a vssim.World as a
batch of one, a vssim.BatchWorld as it is. Both give (n, ...) state arrays,
take (n, robots, 2) commands and place bodies world by world."""

import json


class WorldBatch:
    """One vssim.World as a batch of one world."""

    def __init__(self, world):
        self.world = world
        self.n_worlds = 1
        self.n_robots = world.n_robots
        self.dt = world.dt

    def scene(self):
        return json.loads(self.world.scene_json())

    def state(self):
        """robots (1, r, 5), wheel speeds (1, r, 2), balls (1, 4)."""
        return self.world.robots[None], self.world.wheel_speeds[None], self.world.ball[None]

    def drive(self, commands, wheel_speeds):
        (self.world.set_wheel_speeds if wheel_speeds else self.world.set_voltages)(commands[0])

    def step(self, seconds):
        self.world.step(seconds)

    def reset(self, i):
        self.world.reset()

    def place_robot(self, i, robot, x, y, theta):
        self.world.place_robot(robot, x, y, theta)

    def place_ball(self, i, x, y, vx, vy):
        self.world.place_ball(x, y, vx, vy)

    def close(self):
        self.world.close()


class BatchOfWorlds:
    """A vssim.BatchWorld."""

    def __init__(self, batch):
        self.batch = batch
        self.n_worlds = batch.n_worlds
        self.n_robots = batch.n_robots

    def scene(self):
        return json.loads(self.batch.scene_json())

    def state(self):
        return self.batch.robots, self.batch.wheel_speeds, self.batch.balls

    def drive(self, commands, wheel_speeds):
        (self.batch.set_wheel_speeds if wheel_speeds else self.batch.set_voltages)(commands)

    def step(self, seconds):
        self.batch.step(seconds)

    def reset(self, i):
        self.batch.reset(i)

    def place_robot(self, i, robot, x, y, theta):
        self.batch.place_robot(i, robot, x, y, theta)

    def place_ball(self, i, x, y, vx, vy):
        self.batch.place_ball(i, x, y, vx, vy)

    def close(self):
        pass
