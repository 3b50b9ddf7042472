//! The two velocity profiles of the plugins (runtime spec §1.6 and §2.2). Both are open
//! loop: `v` is the previously commanded velocity, so the motion is deterministic.

/// `copysign(1, x)`, as the plugins use it (`sign(+0) = +1`).
#[inline]
pub(crate) fn sign(x: f64) -> f64 {
    1.0f64.copysign(x)
}

/// Limits of one profile.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Limits {
    pub v_max: f64,
    pub a_max: f64,
    pub a_nom: f64,
}

/// The slotcar's profile (§1.6): next velocity to cover the displacement `s` starting at
/// `v`, cruising at `min(|v_now|, v_max)` and arriving with `v_dest`.
#[inline(always)]
pub(crate) fn robot(s: f64, v: f64, v_now: f64, v_dest: f64, p: Limits, dt: f64) -> f64 {
    let v = if v.abs() < 1e-4 { 0.0 } else { v };
    let opposite = v.abs() > 0.0 && v.is_sign_negative() != s.is_sign_negative();
    if s == 0.0 || opposite {
        return v - sign(v) * v.abs().min(p.a_max * dt);
    }
    let a_req = (v_dest * v_dest - v * v) / (2.0 * s);
    let a_req = a_req.clamp(-p.a_max, p.a_max);
    if a_req.abs() >= p.a_nom {
        return v + a_req * dt;
    }
    let mut v_tgt = sign(s) * v_now.abs().min(p.v_max);
    if ((v + p.a_nom) * dt).abs() > s.abs() {
        v_tgt = sign(s) * (s / dt).abs().max(v_dest);
    }
    let step = p.a_nom * dt;
    v + (v_tgt - v).clamp(-step, step)
}

/// The building plugins' profile (§2.2), used by door joints and lift cabins: a
/// trapezoid at `a_nom` that lands exactly (the `s/dt` cap).
#[inline]
pub(crate) fn building(s: f64, v: f64, p: Limits, dt: f64) -> f64 {
    let (s, v, sg) = if s < 0.0 { (-s, -v, -1.0) } else { (s, v, 1.0) };
    let mut next = (s / dt).min(p.v_max).min(v + p.a_nom * dt);
    if v > 0.0 && s > 0.0 {
        let d = (v * v / (2.0 * s)).min(p.a_max);
        if d >= p.a_nom {
            next = v - d * dt;
        }
    }
    sg * next
}

/// Travel time of a trapezoid (or triangle) over `d` at acceleration `a` up to `v`.
pub(crate) fn trapezoid_time(d: f64, v: f64, a: f64) -> f64 {
    if d >= v * v / a {
        d / v + v / a
    } else {
        2.0 * (d / a).sqrt()
    }
}

/// Time until a trapezoid over `d` comes within `band` of its end: the last `band` of
/// braking at `a` takes `sqrt(2·band/a)` (the plugins' "at target" tests use a band).
#[cfg(test)]
pub(crate) fn time_to_band(d: f64, v: f64, a: f64, band: f64) -> f64 {
    trapezoid_time(d, v, a) - (2.0 * band / a).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Drives the building profile over `d` and returns the time to land.
    fn run_building(d: f64, p: Limits, dt: f64) -> f64 {
        let (mut x, mut v, mut t) = (0.0, 0.0, 0.0);
        while (d - x).abs() >= 1e-4 && t < 1e4 {
            let mut s = d - x;
            if s.abs() < 5e-5 {
                s = 0.0;
            }
            v = building(s, v, p, dt);
            x += v * dt;
            t += dt;
        }
        t
    }

    #[test]
    fn building_profile_matches_trapezoid_time() {
        let p = Limits {
            v_max: 0.2,
            a_max: 0.2,
            a_nom: 0.08,
        };
        for d in [0.5, 1.5, 3.0] {
            let t = run_building(d, p, 0.01);
            let want = time_to_band(d, 0.2, 0.08, 1e-4);
            assert!((t - want).abs() < 0.01 * want, "d={d}: {t} vs {want}");
        }
    }

    #[test]
    fn robot_profile_brakes_at_a_max_when_target_is_zero() {
        let p = Limits {
            v_max: 0.5,
            a_max: 0.1,
            a_nom: 0.05,
        };
        let v = robot(0.0, 0.5, 0.5, 0.0, p, 0.01);
        assert!((v - (0.5 - 0.1 * 0.01)).abs() < 1e-12);
        // Opposite direction: brake, never reverse in one step.
        let v = robot(-1.0, 0.0005, 0.5, 0.0, p, 0.01);
        assert_eq!(v, 0.0);
    }
}
