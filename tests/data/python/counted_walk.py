"""A test policy (tests/integration/test_policy_python.cpp): UAVs walk at
random, drawing from their own stream (uav.rng), and mark each cell they
visit; a place model in Python counts the marks. Lockstep == sim holds only
if every process draws the same numbers and applies the same deposits."""

import pheromesh


class Count(pheromesh.PlaceModel):
    """Each cell holds the number of marks it received, less 1 % a tick."""

    def __init__(self, config, region):
        super().__init__(config, region)
        self.cells = {}

    def apply(self, deposit, tick):
        key = (deposit.layer, deposit.x, deposit.y)
        self.cells[key] = self.cells.get(key, 0.0) + deposit.amount
        return None

    def step(self, tick):
        for key in self.cells:
            self.cells[key] *= 0.99

    def value(self, layer, x, y):
        return self.cells.get((layer, x, y), 0.0)


class CountedWalk(pheromesh.UavPolicy):
    name = "counted_walk"
    parameters = {"mark": 1.0}
    place_model = Count

    @classmethod
    def traits(cls, config):
        return pheromesh.Traits([pheromesh.Layer("marks", max=1e6)], sensor_radius=1.5, view_radius=2.0)

    def __init__(self, config, uav):
        super().__init__(config, uav)
        self.x, self.y = uav.start
        self.heading = 0
        # The test finds this line in the UAV's log: a policy's print() reaches it.
        print(f"counted_walk: uav {uav.id} starts at {uav.start}")

    def step(self, view, actions):
        bx, by = self.x, self.y
        if view.tick > 0:
            # Straight on most of the time, else a random turn; never into an obstacle or off the map.
            if self.uav.rng.uniform01() < 0.3:
                self.heading = self.uav.rng.uniform_below(8)
            for turn in range(8):
                h = pheromesh.rotate(self.heading, turn)
                dx, dy = pheromesh.step_of(h)
                if self.uav.in_map(self.x + dx, self.y + dy) and not self.uav.is_obstacle(self.x + dx, self.y + dy):
                    self.heading = h
                    self.x += dx
                    self.y += dy
                    break
        actions.deposit(0, self.x, self.y, self.config["mark"])
        for t in self.uav.sense(self.x, self.y, 1.5):
            actions.detect(t)
        actions.set_state(self.x, self.y, vx=self.x - bx, vy=self.y - by, heading=self.heading)
