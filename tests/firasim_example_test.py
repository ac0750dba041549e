#!/usr/bin/python3
"""The FIRASim example client's pure functions, without a server
(examples/firasim/go_to_ball.py): the differential-drive conversion, the
go-to-point law and its sign conventions, the striker's target, a kinematic
run of the whole law to the ball, and the placements it answers the
referee with (checked against the rules of docs/game.md, "Placement").
Needs no protobuf: the example imports its generated modules only in main().
"""

import importlib.util
import math
import os
import sys
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
EXAMPLE = os.path.join(HERE, "..", "examples", "firasim", "go_to_ball.py")

spec = importlib.util.spec_from_file_location("go_to_ball", EXAMPLE)
ex = importlib.util.module_from_spec(spec)
spec.loader.exec_module(ex)

ROBOT_HALF = 0.0375    # m, half the side of a 7.5 cm robot
BALL_RADIUS = 0.02135  # m
CENTRE_RADIUS = 0.20   # m


def robot_half_extent(theta):
    """Half the robot's extent along x at heading theta (a square)."""
    return ROBOT_HALF * (abs(math.cos(theta)) + abs(math.sin(theta)))


class WheelSpeeds(unittest.TestCase):
    def test_straight(self):
        left, right = ex.wheel_speeds(0.5, 0.0)
        self.assertAlmostEqual(left, 0.5 / 0.025)
        self.assertAlmostEqual(right, 0.5 / 0.025)

    def test_turning_left_speeds_up_the_right_wheel(self):
        # omega > 0 is counter-clockwise (to the left): the right wheel runs faster.
        left, right = ex.wheel_speeds(0.0, 2.0)
        self.assertAlmostEqual(right, 2.0 * 0.065 / 2 / 0.025)
        self.assertAlmostEqual(left, -right)

    def test_limit_keeps_the_curvature(self):
        left, right = ex.wheel_speeds(3.0, 10.0, limit=50.0)
        self.assertAlmostEqual(max(abs(left), abs(right)), 50.0)
        want_left, want_right = ex.wheel_speeds(3.0, 10.0, limit=1e9)
        self.assertAlmostEqual(left / right, want_left / want_right)

    def test_back_to_body_speeds(self):
        v, omega = 0.3, -1.5
        left, right = ex.wheel_speeds(v, omega)
        self.assertAlmostEqual((right + left) / 2 * 0.025, v)
        self.assertAlmostEqual((right - left) * 0.025 / 0.065, omega)


class GoTo(unittest.TestCase):
    def test_wrap(self):
        self.assertAlmostEqual(ex.wrap(3 * math.pi / 2), -math.pi / 2)
        self.assertAlmostEqual(ex.wrap(-math.pi), math.pi)
        self.assertAlmostEqual(ex.wrap(0.25), 0.25)

    def test_target_ahead(self):
        v, omega = ex.go_to((0.0, 0.0, 0.0), (0.5, 0.0))
        self.assertGreater(v, 0.0)
        self.assertAlmostEqual(omega, 0.0)
        self.assertLessEqual(v, ex.MAX_SPEED)

    def test_target_on_the_left_turns_counter_clockwise(self):
        v, omega = ex.go_to((0.0, 0.0, 0.0), (0.2, 0.2))
        self.assertGreater(v, 0.0)
        self.assertGreater(omega, 0.0)
        v, omega = ex.go_to((0.0, 0.0, math.pi / 2), (-0.2, 0.2))  # facing +y, target to its left
        self.assertGreater(omega, 0.0)

    def test_target_behind_is_reached_backwards(self):
        v, omega = ex.go_to((0.0, 0.0, 0.0), (-0.3, 0.0))
        self.assertLess(v, 0.0)
        self.assertAlmostEqual(omega, 0.0)
        # Behind and to the left: backwards, the back swings towards +y, i.e. clockwise.
        v, omega = ex.go_to((0.0, 0.0, 0.0), (-0.3, 0.1))
        self.assertLess(v, 0.0)
        self.assertLess(omega, 0.0)

    def test_at_the_target(self):
        self.assertEqual(ex.go_to((0.1, 0.2, 1.0), (0.1, 0.2)), (0.0, 0.0))


class Striker(unittest.TestCase):
    def test_goals(self):
        # FIRASim's layout by default: blue on the left attacks x > 0.
        self.assertEqual(ex.opponent_goal("blue"), (0.75, 0.0))
        self.assertEqual(ex.opponent_goal("yellow"), (-0.75, 0.0))
        self.assertEqual(ex.opponent_goal("yellow", left_team="yellow"), (0.75, 0.0))
        self.assertEqual(ex.opponent_goal("blue", left_team="yellow"), (-0.75, 0.0))

    def test_lined_up_pushes_through_the_ball(self):
        self.assertEqual(ex.strike_target((-0.2, 0.0), (0.0, 0.0), (0.75, 0.0)), (0.75, 0.0))

    def test_behind_but_off_the_line_goes_to_the_spot_behind(self):
        x, y = ex.strike_target((-0.3, 0.2), (0.0, 0.0), (0.75, 0.0))
        self.assertAlmostEqual(x, -ex.BEHIND_BALL)
        self.assertAlmostEqual(y, 0.0)

    def test_close_behind_and_off_the_line_pursues_the_line(self):
        x, y = ex.strike_target((-0.06, 0.04), (0.0, 0.0), (0.75, 0.0))
        self.assertAlmostEqual(x, -0.03)
        self.assertAlmostEqual(y, 0.0)

    def test_in_front_goes_round_on_its_side(self):
        x, y = ex.strike_target((0.2, 0.05), (0.0, 0.0), (0.75, 0.0))
        self.assertLess(x, 0.0)
        self.assertGreater(y, 0.0)
        x, y = ex.strike_target((0.2, -0.05), (0.0, 0.0), (0.75, 0.0))
        self.assertLess(y, 0.0)

    def test_aim_past_the_keeper(self):
        # No keeper: the goal's centre. A keeper in the mouth at y > 0: aim
        # below it, and the other way round; a robot far from the goal is no keeper.
        self.assertEqual(ex.aim_point("blue"), (0.75, 0.0))
        self.assertEqual(ex.aim_point("blue", [(0.70, 0.05)]), (0.75, -ex.GOAL_AIM))
        self.assertEqual(ex.aim_point("blue", [(0.70, -0.05)]), (0.75, ex.GOAL_AIM))
        self.assertEqual(ex.aim_point("blue", [(0.20, 0.05)]), (0.75, 0.0))
        self.assertEqual(ex.aim_point("yellow", [(-0.72, 0.1)]), (-0.75, -ex.GOAL_AIM))

    def test_both_teams_drive_forward_at_a_ball_ahead(self):
        left, right = ex.striker_wheels((-0.3, 0.0, 0.0), (0.0, 0.0), "blue")
        self.assertGreater(left, 0.0)
        self.assertAlmostEqual(left, right)
        left, right = ex.striker_wheels((0.3, 0.0, math.pi), (0.0, 0.0), "yellow")
        self.assertGreater(left, 0.0)
        self.assertAlmostEqual(left, right)

    def kinematic_run(self, pose, ball, team, seconds=6.0, dt=0.005):
        """The law on an ideal unicycle (wheels at the commanded speeds); the
        ball stays put. Returns the closest approach to the ball and the
        robot's direction of travel there."""
        x, y, theta = pose
        best = (math.inf, 0.0)
        for _ in range(int(seconds / dt)):
            left, right = ex.striker_wheels((x, y, theta), ball, team)
            v = (left + right) / 2 * ex.WHEEL_RADIUS
            omega = (right - left) * ex.WHEEL_RADIUS / ex.WHEEL_BASE
            x += v * math.cos(theta) * dt
            y += v * math.sin(theta) * dt
            theta = ex.wrap(theta + omega * dt)
            d = math.hypot(ball[0] - x, ball[1] - y)
            if d < best[0]:
                travel = theta if v >= 0 else ex.wrap(theta + math.pi)
                best = (d, travel)
        return best

    def test_blue_reaches_the_ball_heading_for_the_goal_at_positive_x(self):
        # FIRASim's layout: blue, on the left, attacks x > 0.
        distance, travel = self.kinematic_run((-0.4, 0.3, -math.pi / 2), (0.1, -0.1), "blue")
        self.assertLess(distance, ROBOT_HALF + BALL_RADIUS + 0.01)
        goal = math.atan2(0.0 - (-0.1), 0.75 - 0.1)
        self.assertLess(abs(ex.wrap(travel - goal)), math.radians(25))

    def test_yellow_comes_round_the_ball_and_heads_for_negative_x(self):
        # Yellow starts on blue's side of the ball: it must go round it.
        distance, travel = self.kinematic_run((-0.3, 0.05, 0.0), (0.0, 0.0), "yellow", seconds=10.0)
        self.assertLess(distance, ROBOT_HALF + BALL_RADIUS + 0.01)
        self.assertLess(abs(ex.wrap(travel - math.pi)), math.radians(25))


class Placements(unittest.TestCase):
    TEAMS = {"yellow": ex.YELLOW, "blue": ex.BLUE}

    def check_common(self, poses, ids=(0, 1, 2)):
        self.assertEqual([p[0] for p in poses], list(ids))
        for _, x, y, degrees in poses:
            half = robot_half_extent(math.radians(degrees))
            self.assertLessEqual(abs(x) + half, 0.75 + 1e-9)
            self.assertLessEqual(abs(y) + half, 0.65 + 1e-9)
        for i, a in enumerate(poses):
            for b in poses[i + 1:]:
                self.assertGreater(math.hypot(a[1] - b[1], a[2] - b[2]), 2 * ROBOT_HALF * math.sqrt(2))

    def test_kickoff(self):
        for team, colour in self.TEAMS.items():
            own = -ex.attacks_sign(team)
            for favoured in (ex.YELLOW, ex.BLUE):
                poses = ex.placement_for(ex.KICKOFF, favoured, 0, team)
                self.check_common(poses)
                in_circle = 0
                for _, x, y, degrees in poses:
                    self.assertGreaterEqual(own * x, robot_half_extent(math.radians(degrees)))
                    if math.hypot(x, y) < CENTRE_RADIUS:
                        in_circle += 1
                        self.assertGreater(math.hypot(x, y), ROBOT_HALF * math.sqrt(2) + BALL_RADIUS)
                self.assertEqual(in_circle, 1 if favoured == colour else 0)

    def test_free_ball_keeps_the_distance(self):
        for team in self.TEAMS:
            for quadrant in (1, 2, 3, 4):
                bx = 0.375 if quadrant in (1, 4) else -0.375
                by = 0.25 if quadrant in (1, 2) else -0.25
                poses = ex.placement_for(ex.FREE_BALL, ex.NONE, quadrant, team)
                self.check_common(poses)
                for _, x, y, _ in poses:
                    self.assertGreaterEqual(math.hypot(x - bx, y - by), 0.19)
                # The kicker 0.20 m from the ball along x, on its own side.
                _, x, y, _ = poses[1]
                self.assertAlmostEqual(x, bx + ex.attacks_sign(team) * -0.20)
                self.assertAlmostEqual(y, by)

    def test_penalty_and_goal_kick(self):
        for team, colour in self.TEAMS.items():
            att = ex.attacks_sign(team)
            for favoured in (ex.YELLOW, ex.BLUE):
                for foul in (ex.PENALTY_KICK, ex.GOAL_KICK):
                    self.check_common(ex.placement_for(foul, favoured, 0, team))
            # Our penalty: the kicker behind the mark in the other half, facing that goal.
            _, x, y, degrees = ex.placement_for(ex.PENALTY_KICK, colour, 0, team)[1]
            self.assertAlmostEqual(x, att * 0.275)
            self.assertEqual(degrees, 0.0 if att > 0 else 180.0)
            # A penalty against us: everyone but the keeper in the other half.
            for _, x, _, degrees in ex.placement_for(ex.PENALTY_KICK, 1 - colour, 0, team)[1:]:
                self.assertGreaterEqual(att * x, robot_half_extent(math.radians(degrees)))

    def test_fewer_robots(self):
        self.assertEqual(len(ex.placement_for(ex.KICKOFF, ex.YELLOW, 0, "yellow", ids=[0, 1])), 2)


if __name__ == "__main__":
    unittest.main(verbosity=2)
