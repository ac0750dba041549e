#include "vssim/collision_response.h"

#include <cmath>
#include <limits>

#include "vssim/geometry.h"

namespace vssim {

namespace {

Eigen::Vector2d heading(const RobotState& r) {
    const CosSin h = cosSin(r.theta);
    return {h.c, h.s};
}
Eigen::Vector2d perp(const Eigen::Vector2d& d) { return {-d.y(), d.x()}; }  // z x d
double cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

Eigen::Vector2d leverArm(const RobotState& r, const Eigen::Vector2d& point) {
    return point - Eigen::Vector2d(r.x, r.y);
}

// Translational mass of a body, kg (infinite for a wall).
double massOf(const Bodies& bodies, const BodyRef& body) {
    switch (body.kind) {
        case BodyKind::Robot: return (*bodies.models)[body.index].params.mass;
        case BodyKind::Ball: return bodies.ballParams->mass;
        case BodyKind::Wall: break;
    }
    return std::numeric_limits<double>::infinity();
}

// Sets a body's contact-point velocity to `wanted` (paper model).
void setContactPointVelocity(Bodies& bodies, const BodyRef& body, const Eigen::Vector2d& point,
                             const Eigen::Vector2d& wanted) {
    if (body.kind == BodyKind::Robot) {
        RobotState& r = (*bodies.robots)[body.index];
        const Eigen::Vector2d u = decomposeContactVelocity(r, leverArm(r, point), wanted);
        r.v = u(0);
        r.omega = u(1);
    } else if (body.kind == BodyKind::Ball) {
        bodies.ball->vx = wanted.x();
        bodies.ball->vy = wanted.y();
    }
}

// Kinetic energy of one body (robot: 1/2 u^T M u; ball: 1/2 m |v|^2), J.
double bodyEnergy(const Bodies& bodies, const BodyRef& body) {
    if (body.kind == BodyKind::Robot) {
        const RobotState& r = (*bodies.robots)[body.index];
        const Eigen::Vector2d u(r.v, r.omega);
        return 0.5 * u.dot((*bodies.models)[body.index].M * u);
    }
    if (body.kind == BodyKind::Ball)
        return 0.5 * bodies.ballParams->mass * (bodies.ball->vx * bodies.ball->vx + bodies.ball->vy * bodies.ball->vy);
    return 0.0;
}

// The velocities a response may change, to undo it.
struct SavedVelocities {
    RobotState a, b;
    BallState ball;
};

SavedVelocities save(const Bodies& bodies, const Contact& c) {
    SavedVelocities s;
    if (c.a.kind == BodyKind::Robot) s.a = (*bodies.robots)[c.a.index];
    if (c.b.kind == BodyKind::Robot) s.b = (*bodies.robots)[c.b.index];
    if (bodies.ball) s.ball = *bodies.ball;
    return s;
}

void restore(Bodies& bodies, const Contact& c, const SavedVelocities& s) {
    if (c.a.kind == BodyKind::Robot) (*bodies.robots)[c.a.index] = s.a;
    if (c.b.kind == BodyKind::Robot) (*bodies.robots)[c.b.index] = s.b;
    if (bodies.ball) *bodies.ball = s.ball;
}

bool respondImpulse(const Contact& c, Bodies& bodies, double restitution);

bool respondPaper(const Contact& c, Bodies& bodies) {
    const Eigen::Vector2d va = contactPointVelocity(bodies, c.a, c.point);
    const Eigen::Vector2d vb = contactPointVelocity(bodies, c.b, c.point);
    const double na = va.dot(c.normal), nb = vb.dot(c.normal);
    if (na - nb >= 0.0) return false;  // separating or resting
    const double energyBefore = bodyEnergy(bodies, c.a) + bodyEnergy(bodies, c.b);
    const SavedVelocities saved = save(bodies, c);
    const Eigen::Vector2d after = elasticExchange(massOf(bodies, c.a), na, massOf(bodies, c.b), nb);
    setContactPointVelocity(bodies, c.a, c.point, va + (after(0) - na) * c.normal);
    setContactPointVelocity(bodies, c.b, c.point, vb + (after(1) - nb) * c.normal);
    // The equivalent sphere ignores the lever arm, so near a robot's lateral
    // axis the exchange can ask for a huge yaw rate and create energy; left
    // alone, a pile of robots then spins up without bound. There the elastic
    // impulse (§6b with restitution 1) takes over, which conserves energy.
    const double energyAfter = bodyEnergy(bodies, c.a) + bodyEnergy(bodies, c.b);
    if (energyAfter > energyBefore * (1.0 + kPaperEnergyTolerance) + 1e-15) {
        restore(bodies, c, saved);
        return respondImpulse(c, bodies, 1.0);
    }
    return true;
}

// §6b: the normal velocity of a contact point is g . u; an impulse lambda
// along n changes u by M^-1 g^T lambda.
struct ImpulseSide {
    double normalSpeed = 0.0;  // g . u, m/s
    double inverseMass = 0.0;  // g M^-1 g^T, 1/kg
    Eigen::Vector2d g = Eigen::Vector2d::Zero();
};

ImpulseSide impulseSide(const Bodies& bodies, const BodyRef& body, const Eigen::Vector2d& point,
                        const Eigen::Vector2d& n) {
    ImpulseSide s;
    if (body.kind == BodyKind::Robot) {
        const RobotState& r = (*bodies.robots)[body.index];
        const RobotModel& m = (*bodies.models)[body.index];
        s.g = Eigen::Vector2d(n.dot(heading(r)), cross(leverArm(r, point), n));
        s.normalSpeed = s.g.dot(Eigen::Vector2d(r.v, r.omega));
        s.inverseMass = s.g.dot(m.Minv * s.g);
    } else if (body.kind == BodyKind::Ball) {
        s.normalSpeed = n.dot(Eigen::Vector2d(bodies.ball->vx, bodies.ball->vy));
        s.inverseMass = 1.0 / bodies.ballParams->mass;
    }
    return s;
}

void applyImpulse(Bodies& bodies, const BodyRef& body, const ImpulseSide& side, const Eigen::Vector2d& n,
                  double lambda) {
    if (body.kind == BodyKind::Robot) {
        RobotState& r = (*bodies.robots)[body.index];
        const Eigen::Vector2d du = (*bodies.models)[body.index].Minv * side.g * lambda;
        r.v += du(0);
        r.omega += du(1);
    } else if (body.kind == BodyKind::Ball) {
        const double scale = lambda / bodies.ballParams->mass;
        bodies.ball->vx += scale * n.x();
        bodies.ball->vy += scale * n.y();
    }
}

bool respondImpulse(const Contact& c, Bodies& bodies, double restitution) {
    const ImpulseSide a = impulseSide(bodies, c.a, c.point, c.normal);
    const ImpulseSide b = impulseSide(bodies, c.b, c.point, c.normal);
    const double approach = a.normalSpeed - b.normalSpeed;
    const double inverseMass = a.inverseMass + b.inverseMass;
    if (approach >= 0.0 || inverseMass <= 0.0) return false;
    const double lambda = -(1.0 + restitution) * approach / inverseMass;  // N s
    applyImpulse(bodies, c.a, a, c.normal, lambda);
    applyImpulse(bodies, c.b, b, c.normal, -lambda);
    return true;
}

void translate(Bodies& bodies, const BodyRef& body, const Eigen::Vector2d& delta) {
    if (body.kind == BodyKind::Robot) {
        (*bodies.robots)[body.index].x += delta.x();
        (*bodies.robots)[body.index].y += delta.y();
    } else if (body.kind == BodyKind::Ball) {
        bodies.ball->x += delta.x();
        bodies.ball->y += delta.y();
    }
}

}  // namespace

Eigen::Vector2d contactPointVelocity(const Bodies& bodies, const BodyRef& body, const Eigen::Vector2d& point) {
    switch (body.kind) {
        case BodyKind::Robot: {
            const RobotState& r = (*bodies.robots)[body.index];
            return r.v * heading(r) + r.omega * perp(leverArm(r, point));
        }
        case BodyKind::Ball: return {bodies.ball->vx, bodies.ball->vy};
        case BodyKind::Wall: break;
    }
    return Eigen::Vector2d::Zero();
}

Eigen::Vector2d decomposeContactVelocity(const RobotState& robot, const Eigen::Vector2d& d,
                                         const Eigen::Vector2d& wanted) {
    const Eigen::Vector2d h = heading(robot);
    const Eigen::Vector2d hPerp = perp(h);
    const double forward = d.dot(h);      // d_f, m
    const double lateral = d.dot(hPerp);  // d_l, m
    if (std::abs(forward) < kLateralAxisTolerance) {
        const Eigen::Vector2d current = robot.v * h + robot.omega * perp(d);
        return {robot.v + h.dot(wanted - current), robot.omega};
    }
    // v_c = (v - w d_l) h + w d_f h_perp.
    const double omega = wanted.dot(hPerp) / forward;
    return {wanted.dot(h) + omega * lateral, omega};
}

Eigen::Vector2d elasticExchange(double m1, double v1, double m2, double v2) {
    if (std::isinf(m1) && std::isinf(m2)) return {v1, v2};
    if (std::isinf(m2)) return {2.0 * v2 - v1, v2};  // wall: the normal component reverses
    if (std::isinf(m1)) return {v1, 2.0 * v1 - v2};
    const double sum = m1 + m2;
    return {((m1 - m2) * v1 + 2.0 * m2 * v2) / sum, ((m2 - m1) * v2 + 2.0 * m1 * v1) / sum};
}

bool respondToContact(const Contact& contact, Bodies& bodies, CollisionModel model, double restitution) {
    return model == CollisionModel::Paper ? respondPaper(contact, bodies)
                                          : respondImpulse(contact, bodies, restitution);
}

void separateBodies(const Contact& contact, Bodies& bodies) {
    const double wa = 1.0 / massOf(bodies, contact.a);  // 0 for a wall
    const double wb = 1.0 / massOf(bodies, contact.b);
    if (wa + wb <= 0.0 || contact.depth <= 0.0) return;
    translate(bodies, contact.a, contact.normal * (contact.depth * wa / (wa + wb)));
    translate(bodies, contact.b, -contact.normal * (contact.depth * wb / (wa + wb)));
}

double kineticEnergy(const Bodies& bodies) {
    double energy = 0.0;
    for (std::size_t i = 0; i < bodies.robots->size(); ++i) {
        const RobotState& r = (*bodies.robots)[i];
        const Eigen::Vector2d u(r.v, r.omega);
        energy += 0.5 * u.dot((*bodies.models)[i].M * u);
    }
    if (bodies.ball)
        energy +=
            0.5 * bodies.ballParams->mass * (bodies.ball->vx * bodies.ball->vx + bodies.ball->vy * bodies.ball->vy);
    return energy;
}

}  // namespace vssim
