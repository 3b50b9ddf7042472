//! WGS 84 longitude/latitude to an EPSG projected CRS, as PROJ does it.
//!
//! `data/epsg.txt` is generated from PROJ's database by `tools/crs/gen_epsg.py` (never
//! edited by hand): for every projected CRS, the candidate operations PROJ's
//! `proj_create_crs_to_crs` chooses from (no grid files), each with its area of use,
//! accuracy and pipeline steps. Per point we pick the operation as PROJ's `proj_trans` does
//! (best accuracy among the areas containing the point, onshore before offshore, smaller
//! area on ties) and run its steps: unit conversion, geocentric conversion, Helmert and
//! Molodensky-Badekas datum shifts, geographic offsets, axis swaps here, and the map
//! projections with `proj4rs` (the same algorithms as PROJ's).

use std::f64::consts::PI;

const TABLE: &str = include_str!("../data/epsg.txt");

/// What the table says about an EPSG code.
pub enum Lookup {
    Crs(Crs),
    /// A projected CRS whose axes are not in metres (its unit's name).
    NotMetres(String),
    /// A CRS mapc cannot project to, and why.
    Refused(String),
    /// Not a projected CRS of the EPSG database.
    Unknown,
}

pub struct Crs {
    ops: Vec<Op>,
}

struct Op {
    /// Area of use: west, south, east, north in degrees (west > east crosses 180°).
    area: [f64; 4],
    /// Metres; negative when unknown (ballpark operations).
    accuracy: f64,
    offshore: bool,
    unknown_area: bool,
    steps: Vec<Step>,
}

enum Step {
    /// Multiplies x and y (degrees to radians and back).
    Scale(f64),
    Push,
    Pop,
    /// Geodetic (radians, metres) to geocentric, or back when `inv`.
    Cart {
        a: f64,
        es: f64,
        inv: bool,
    },
    /// 7-parameter Helmert (position vector rotation matrix `r`, as PROJ builds it with
    /// small angles) about `pivot` (zero unless Molodensky-Badekas).
    Helmert {
        t: [f64; 3],
        r: [[f64; 3]; 3],
        scale: f64,
        pivot: [f64; 3],
        inv: bool,
    },
    /// Adds arc-second offsets to longitude and latitude.
    GeogOffset {
        dlon: f64,
        dlat: f64,
        inv: bool,
    },
    /// PROJ's `axisswap order=a,b`: output axis i is input axis |o_i| - 1, negated if o_i < 0.
    AxisSwap([i32; 2]),
    /// EPSG method 1052, Colombia Urban (not in proj4rs): EPSG guidance note 7-2 §3.3.
    ColUrban {
        a: f64,
        es: f64,
        phi0: f64,
        lam0: f64,
        x0: f64,
        y0: f64,
        h0: f64,
    },
    /// EPSG method 9811, New Zealand Map Grid (not in proj4rs): PROJ's nzmg.cpp forward,
    /// a complex polynomial of the isometric-latitude series.
    Nzmg {
        a: f64,
        phi0: f64,
        lam0: f64,
        x0: f64,
        y0: f64,
    },
    /// EPSG method 9813, Laborde Oblique Mercator (not in proj4rs): PROJ's labrd.cpp
    /// forward. `lam0` includes the prime meridian.
    Labrd {
        a: f64,
        e: f64,
        lam0: f64,
        k_rg: f64,
        p0s: f64,
        big_a: f64,
        big_c: f64,
        ca: f64,
        cb: f64,
        x0: f64,
        y0: f64,
    },
    /// A map projection or `longlat` with a prime meridian, run by proj4rs from the
    /// geographic CRS on the same ellipsoid.
    Proj {
        geo: Box<proj4rs::Proj>,
        proj: Box<proj4rs::Proj>,
        inv: bool,
    },
}

/// Looks `code` up; `Lookup::Refused` when a step is one mapc does not implement.
pub fn lookup(code: u32) -> Lookup {
    let key = format!("C {code} ");
    let mut lines = TABLE.lines().skip_while(|l| !l.starts_with(&key));
    let Some(head) = lines.next() else {
        return Lookup::Unknown;
    };
    let rest = &head[key.len()..];
    if let Some(unit) = rest.strip_prefix("u ") {
        return Lookup::NotMetres(unit.to_string());
    }
    if let Some(reason) = rest.strip_prefix("! ") {
        return Lookup::Refused(reason.to_string());
    }
    let op_lines: Vec<&str> = lines.take_while(|l| l.starts_with("O ")).collect();
    let mut ops = Vec::new();
    for line in op_lines {
        match parse_op(line) {
            Ok(op) => ops.push(op),
            Err(reason) => return Lookup::Refused(reason),
        }
    }
    if ops.is_empty() {
        return Lookup::Refused("the table lists no operation for it".into());
    }
    Lookup::Crs(Crs { ops })
}

/// Every EPSG code of the table (all projected CRSs of PROJ's EPSG database), ascending.
pub fn codes() -> impl Iterator<Item = u32> {
    TABLE
        .lines()
        .filter_map(|l| l.strip_prefix("C "))
        .filter_map(|l| l.split(' ').next()?.parse().ok())
}

fn step_text(id: usize) -> Option<&'static str> {
    let key = format!("S {id} ");
    TABLE
        .lines()
        .take_while(|l| l.starts_with('S') || l.starts_with('#'))
        .find_map(|l| l.strip_prefix(&key))
}

fn parse_op(line: &str) -> Result<Op, String> {
    let f: Vec<&str> = line.split(' ').collect();
    let bad = || format!("malformed table line `{line}`");
    if f.len() != 8 {
        return Err(bad());
    }
    let num = |s: &str| s.parse::<f64>().map_err(|_| bad());
    let area = [num(f[1])?, num(f[2])?, num(f[3])?, num(f[4])?];
    let mut steps = Vec::new();
    for id in f[7].split(',') {
        let id: usize = id.parse().map_err(|_| bad())?;
        let text = step_text(id).ok_or_else(bad)?;
        steps.push(parse_step(text)?);
    }
    Ok(Op {
        area,
        accuracy: num(f[5])?,
        offshore: f[6].contains('o'),
        unknown_area: f[6].contains('u'),
        steps,
    })
}

/// `[inv ]proj=NAME k=v ...` (a step of a PROJ pipeline definition).
fn parse_step(text: &str) -> Result<Step, String> {
    let (inv, body) = match text.strip_prefix("inv ") {
        Some(b) => (true, b),
        None => (false, text),
    };
    let params: Vec<(&str, &str)> = body
        .split(' ')
        .map(|t| t.split_once('=').unwrap_or((t, "")))
        .collect();
    let get = |k: &str| params.iter().find(|(n, _)| *n == k).map(|(_, v)| *v);
    let num = |k: &str| -> Result<f64, String> {
        match get(k) {
            None => Ok(0.0),
            Some(v) => v
                .parse()
                .map_err(|_| format!("PROJ step `{text}`: `{k}` is not a number")),
        }
    };
    let name = get("proj").unwrap_or("");
    let ellipsoid = || -> Result<(f64, f64), String> {
        let def: Vec<String> = params
            .iter()
            .filter(|(k, _)| matches!(*k, "ellps" | "a" | "b" | "rf" | "R"))
            .map(|(k, v)| format!("+{k}={v}"))
            .collect();
        let p = proj4rs::Proj::from_proj_string(&format!("+proj=longlat {}", def.join(" ")))
            .map_err(|e| format!("PROJ step `{text}`: {e}"))?;
        let (a, b) = p.ellipse_parameters();
        Ok((a, 1.0 - (b * b) / (a * a)))
    };
    Ok(match name {
        "unitconvert" => {
            let factor = |u: Option<&str>| match u {
                Some("deg") => Ok(PI / 180.0),
                Some("rad") => Ok(1.0),
                _ => Err(format!("PROJ step `{text}`: unsupported unit conversion")),
            };
            let f = factor(get("xy_in"))? / factor(get("xy_out"))?;
            Step::Scale(if inv { 1.0 / f } else { f })
        }
        "push" => Step::Push,
        "pop" => Step::Pop,
        "cart" => {
            let (a, es) = ellipsoid()?;
            Step::Cart { a, es, inv }
        }
        "helmert" | "molobadekas" => {
            if get("exact").is_some() || get("theta").is_some() || get("t_epoch").is_some() {
                return Err(format!("PROJ step `{text}`: unsupported Helmert variant"));
            }
            let sec = PI / 180.0 / 3600.0;
            let (rx, ry, rz) = (num("rx")? * sec, num("ry")? * sec, num("rz")? * sec);
            // PROJ's small-angle matrix in the coordinate frame convention, transposed for
            // position vector (helmert.cpp, build_rot_matrix).
            let cf = [[1.0, rz, -ry], [-rz, 1.0, rx], [ry, -rx, 1.0]];
            let r = match get("convention") {
                Some("coordinate_frame") => cf,
                Some("position_vector") | None => transpose(cf),
                Some(c) => return Err(format!("PROJ step `{text}`: convention {c}")),
            };
            Step::Helmert {
                t: [num("x")?, num("y")?, num("z")?],
                r,
                scale: 1.0 + num("s")? * 1e-6,
                pivot: [num("px")?, num("py")?, num("pz")?],
                inv,
            }
        }
        "geogoffset" => {
            if get("dh").is_some() {
                // Heights do not matter to a 2D projection.
            }
            let sec = PI / 180.0 / 3600.0;
            Step::GeogOffset {
                dlon: num("dlon")? * sec,
                dlat: num("dlat")? * sec,
                inv,
            }
        }
        "axisswap" => {
            let order: Vec<i32> = get("order")
                .unwrap_or("")
                .split(',')
                .filter_map(|s| s.parse().ok())
                .collect();
            match order[..] {
                [a, b] if (1..=2).contains(&a.abs()) && (1..=2).contains(&b.abs()) => {
                    Step::AxisSwap([a, b])
                }
                _ => return Err(format!("PROJ step `{text}`: unsupported axis order")),
            }
        }
        "col_urban" if !inv => {
            let (a, es) = ellipsoid()?;
            Step::ColUrban {
                a,
                es,
                phi0: num("lat_0")?.to_radians(),
                lam0: num("lon_0")?.to_radians(),
                x0: num("x_0")?,
                y0: num("y_0")?,
                h0: num("h_0")?,
            }
        }
        "labrd" if !inv => {
            let (a, es) = ellipsoid()?;
            let pm = match get("pm") {
                None => 0.0,
                Some("paris") => 2.337_229_166_666_667,
                Some(v) => v
                    .parse()
                    .map_err(|_| format!("PROJ step `{text}`: prime meridian {v}"))?,
            };
            let phi0 = num("lat_0")?.to_radians();
            let k0 = get("k").or(get("k_0")).map_or(Ok(1.0), |v| {
                v.parse::<f64>()
                    .map_err(|_| format!("PROJ step `{text}`: `k` is not a number"))
            })?;
            let e = es.sqrt();
            let sinp = phi0.sin();
            let t = 1.0 - es * sinp * sinp;
            let n = 1.0 / t.sqrt();
            let r = (1.0 - es) * n / t;
            let k_rg = k0 * (n * r).sqrt();
            let p0s = ((r / n).sqrt() * phi0.tan()).atan();
            let big_a = sinp / p0s.sin();
            let t = e * sinp;
            let fortpi = std::f64::consts::FRAC_PI_4;
            let big_c = 0.5 * e * big_a * ((1.0 + t) / (1.0 - t)).ln()
                - big_a * (fortpi + 0.5 * phi0).tan().ln()
                + (fortpi + 0.5 * p0s).tan().ln();
            let az2 = 2.0 * num("azi")?.to_radians();
            let cb = 1.0 / (12.0 * k_rg * k_rg);
            Step::Labrd {
                a,
                e,
                lam0: (num("lon_0")? + pm).to_radians(),
                k_rg,
                p0s,
                big_a,
                big_c,
                ca: (1.0 - az2.cos()) * cb,
                cb: cb * az2.sin(),
                x0: num("x_0")?,
                y0: num("y_0")?,
            }
        }
        "nzmg" if !inv => {
            let (a, _) = ellipsoid()?;
            Step::Nzmg {
                a,
                phi0: num("lat_0")?.to_radians(),
                lam0: num("lon_0")?.to_radians(),
                x0: num("x_0")?,
                y0: num("y_0")?,
            }
        }
        _ => {
            let def: Vec<String> = params.iter().map(|(k, v)| plus(k, v)).collect();
            let proj = proj4rs::Proj::from_proj_string(&def.join(" ")).map_err(|_| {
                format!("the projection method `{name}` is not implemented in mapc")
            })?;
            // The geographic CRS on the same ellipsoid, so proj4rs applies no datum shift.
            let ell: Vec<String> = params
                .iter()
                .filter(|(k, _)| matches!(*k, "ellps" | "a" | "b" | "rf" | "R"))
                .map(|(k, v)| plus(k, v))
                .collect();
            let geo = proj4rs::Proj::from_proj_string(&format!("+proj=longlat {}", ell.join(" ")))
                .map_err(|e| format!("PROJ step `{text}`: {e}"))?;
            Step::Proj {
                geo: Box::new(geo),
                proj: Box::new(proj),
                inv,
            }
        }
    })
}

fn plus(k: &str, v: &str) -> String {
    if v.is_empty() {
        format!("+{k}")
    } else {
        format!("+{k}={v}")
    }
}

fn transpose(m: [[f64; 3]; 3]) -> [[f64; 3]; 3] {
    let mut t = [[0.0; 3]; 3];
    for (i, row) in m.iter().enumerate() {
        for (j, v) in row.iter().enumerate() {
            t[j][i] = *v;
        }
    }
    t
}

impl Crs {
    /// Easting and northing in metres of a WGS 84 longitude/latitude in degrees.
    pub fn project(&self, lon: f64, lat: f64) -> Option<(f64, f64)> {
        let op = &self.ops[self.choose(lon, lat)];
        let mut p = [lon, lat, 0.0];
        let mut stack = Vec::new();
        for step in &op.steps {
            p = run(step, p, &mut stack)?;
        }
        (p[0].is_finite() && p[1].is_finite()).then_some((p[0], p[1]))
    }

    /// PROJ's `pj_get_suggested_operation` for a lon/lat source: among the operations
    /// whose area holds the point, the first of best known accuracy, preferring the
    /// smaller area on equal accuracy and never switching to an offshore one; the first
    /// operation when no area holds the point (all ours need no grid).
    fn choose(&self, lon: f64, lat: f64) -> usize {
        let mut best: Option<usize> = None;
        let mut best_acc = f64::MAX;
        for (i, op) in self.ops.iter().enumerate() {
            let [w, s, e, n] = op.area;
            let inside_lon = if w <= e {
                lon >= w && lon <= e
            } else {
                lon >= w || lon <= e
            };
            if !(inside_lon && lat >= s && lat <= n) {
                continue;
            }
            let take = match best {
                None => true,
                Some(b) => {
                    let cur = &self.ops[b];
                    ((op.accuracy >= 0.0 && op.accuracy < best_acc)
                        || (op.accuracy == best_acc
                            && op.pseudo_area() < cur.pseudo_area()
                            // An unknown area never displaces a known one.
                            && (!op.unknown_area || cur.unknown_area)))
                        && !op.offshore
                }
            };
            if take {
                best = Some(i);
                best_acc = op.accuracy;
            }
        }
        best.unwrap_or(0)
    }
}

impl Op {
    fn pseudo_area(&self) -> f64 {
        let [w, s, e, n] = self.area;
        let width = if w <= e { e - w } else { e - w + 360.0 };
        width * (n - s)
    }
}

fn run(step: &Step, p: [f64; 3], stack: &mut Vec<f64>) -> Option<[f64; 3]> {
    let [x, y, z] = p;
    Some(match step {
        Step::Scale(f) => [x * f, y * f, z],
        Step::Push => {
            stack.push(z);
            p
        }
        Step::Pop => [x, y, stack.pop()?],
        Step::Cart { a, es, inv: false } => {
            let (sl, cl) = x.sin_cos();
            let (sp, cp) = y.sin_cos();
            let nu = a / (1.0 - es * sp * sp).sqrt();
            [
                (nu + z) * cp * cl,
                (nu + z) * cp * sl,
                (nu * (1.0 - es) + z) * sp,
            ]
        }
        Step::Cart { a, es, inv: true } => geodetic(*a, *es, p),
        Step::Helmert {
            t,
            r,
            scale,
            pivot,
            inv,
        } => {
            if !inv {
                let q = [p[0] - pivot[0], p[1] - pivot[1], p[2] - pivot[2]];
                let mut out = [0.0; 3];
                for i in 0..3 {
                    out[i] = scale * (r[i][0] * q[0] + r[i][1] * q[1] + r[i][2] * q[2])
                        + t[i]
                        + pivot[i];
                }
                out
            } else {
                // As PROJ: undo translation and scale, then rotate by the transpose.
                let q = [
                    (p[0] - t[0] - pivot[0]) / scale,
                    (p[1] - t[1] - pivot[1]) / scale,
                    (p[2] - t[2] - pivot[2]) / scale,
                ];
                let mut out = [0.0; 3];
                for i in 0..3 {
                    out[i] = r[0][i] * q[0] + r[1][i] * q[1] + r[2][i] * q[2] + pivot[i];
                }
                out
            }
        }
        Step::GeogOffset { dlon, dlat, inv } => {
            let sign = if *inv { -1.0 } else { 1.0 };
            [x + sign * dlon, y + sign * dlat, z]
        }
        Step::AxisSwap(order) => {
            let pick = |o: i32| {
                let v = p[(o.unsigned_abs() - 1) as usize];
                if o < 0 {
                    -v
                } else {
                    v
                }
            };
            [pick(order[0]), pick(order[1]), z]
        }
        Step::ColUrban {
            a,
            es,
            phi0,
            lam0,
            x0,
            y0,
            h0,
        } => {
            let nu = |phi: f64| a / (1.0 - es * phi.sin().powi(2)).sqrt();
            let rho = |phi: f64| a * (1.0 - es) / (1.0 - es * phi.sin().powi(2)).powf(1.5);
            let (nu0, rho0) = (nu(*phi0), rho(*phi0));
            let big_a = 1.0 + h0 / nu0;
            let big_b = phi0.tan() / (2.0 * rho0 * nu0);
            let big_g = 1.0 + h0 / rho((y + phi0) / 2.0);
            let l = (x - lam0) * nu(y) * y.cos();
            [
                x0 + big_a * l,
                y0 + big_g * rho0 * ((y - phi0) + big_b * l * l),
                z,
            ]
        }
        Step::Nzmg {
            a,
            phi0,
            lam0,
            x0,
            y0,
        } => {
            let (re, im) = nzmg(y - phi0, x - lam0);
            [x0 + a * re, y0 + a * im, z]
        }
        Step::Labrd {
            a,
            e,
            lam0,
            k_rg,
            p0s,
            big_a,
            big_c,
            ca,
            cb,
            x0,
            y0,
        } => {
            let fortpi = std::f64::consts::FRAC_PI_4;
            let (lam, phi) = (x - lam0, y);
            let v1 = big_a * (fortpi + 0.5 * phi).tan().ln();
            let t = e * phi.sin();
            let v2 = 0.5 * e * big_a * ((1.0 + t) / (1.0 - t)).ln();
            let ps = 2.0 * ((v1 - v2 + big_c).exp().atan() - fortpi);
            let i1 = ps - p0s;
            let (sinps, cosps) = ps.sin_cos();
            let (sinps2, cosps2) = (sinps * sinps, cosps * cosps);
            let i4 = big_a * cosps;
            let i2 = 0.5 * big_a * i4 * sinps;
            let i3 = i2 * big_a * big_a * (5.0 * cosps2 - sinps2) / 12.0;
            let mut i6 = i4 * big_a * big_a;
            let i5 = i6 * (cosps2 - sinps2) / 6.0;
            i6 *=
                big_a * big_a * (5.0 * cosps2 * cosps2 + sinps2 * (sinps2 - 18.0 * cosps2)) / 120.0;
            let t = lam * lam;
            let mut xx = k_rg * lam * (i4 + t * (i5 + t * i6));
            let mut yy = k_rg * (i1 + t * (i2 + t * i3));
            let (x2, y2) = (xx * xx, yy * yy);
            let w1 = 3.0 * xx * y2 - xx * x2;
            let w2 = yy * y2 - 3.0 * x2 * yy;
            xx += ca * w1 + cb * w2;
            yy += ca * w2 - cb * w1;
            [x0 + a * xx, y0 + a * yy, z]
        }
        Step::Proj { geo, proj, inv } => {
            let mut pt = (x, y, z);
            let (from, to) = if *inv { (proj, geo) } else { (geo, proj) };
            proj4rs::transform::transform(from, to, &mut pt).ok()?;
            [pt.0, pt.1, pt.2]
        }
    })
}

/// New Zealand Map Grid on the unit ellipsoid: (easting, northing) of latitude and
/// longitude offsets from the origin in radians. Coefficients from PROJ's nzmg.cpp (the
/// published LINZ series).
fn nzmg(dphi: f64, dlam: f64) -> (f64, f64) {
    const RAD_TO_SEC5: f64 = 2.062_648_062_470_963_6;
    const TPSI: [f64; 10] = [
        0.6399175073,
        -0.1358797613,
        0.063294409,
        -0.02526853,
        0.0117879,
        -0.0055161,
        0.0026906,
        -0.001333,
        0.00067,
        -0.00034,
    ];
    const BF: [(f64, f64); 6] = [
        (0.7557853228, 0.0),
        (0.249204646, 0.003371507),
        (-0.001541739, 0.041058560),
        (-0.10162907, 0.01727609),
        (-0.26623489, -0.36249218),
        (-0.6870983, -1.1651967),
    ];
    let phi = dphi * RAD_TO_SEC5;
    let psi = TPSI.iter().rev().fold(0.0, |acc, c| c + phi * acc) * phi;
    // z * (b0 + z * (b1 + ... )), z = psi + i lam (Horner, as pj_zpoly1).
    let (zr, zi) = (psi, dlam);
    let (mut ar, mut ai) = BF[5];
    for &(br, bi) in BF[..5].iter().rev() {
        let t = ar;
        ar = br + zr * t - zi * ai;
        ai = bi + zr * ai + zi * t;
    }
    let t = ar;
    let (re, im) = (zr * t - zi * ai, zr * ai + zi * t);
    // PROJ's x is the imaginary part (easting), y the real part (northing).
    (im, re)
}

/// Geocentric to geodetic (longitude, latitude in radians, height), iterated to
/// convergence: far below a millimetre for any point near the ellipsoid.
fn geodetic(a: f64, es: f64, p: [f64; 3]) -> [f64; 3] {
    let [x, y, z] = p;
    let lon = y.atan2(x);
    let r = x.hypot(y);
    let mut lat = z.atan2(r * (1.0 - es));
    let mut h = 0.0;
    for _ in 0..10 {
        let s = lat.sin();
        let nu = a / (1.0 - es * s * s).sqrt();
        h = if lat.cos().abs() > 1e-9 {
            r / lat.cos() - nu
        } else {
            z.abs() - nu * (1.0 - es)
        };
        let next = z.atan2(r * (1.0 - es * nu / (nu + h)));
        if (next - lat).abs() < 1e-14 {
            lat = next;
            break;
        }
        lat = next;
    }
    [lon, lat, h]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The example: EPSG:5174 needs Korean 1985's datum shift (about 360 m). The
    /// expected numbers are PROJ's: pyproj 3.7.2 / PROJ 9.5.1,
    /// `Transformer.from_crs(4326, 5174, always_xy=True).transform(127.77, 35.89)`.
    #[test]
    fn korean_1985_has_its_datum_shift() {
        let Lookup::Crs(crs) = lookup(5174) else {
            panic!("5174 not found")
        };
        let (e, n) = crs.project(127.77, 35.89).unwrap();
        let (pe, pn) = (269450.9374786186, 265805.4889725979);
        assert!((e - pe).hypot(n - pn) < 1e-3, "{e} {n}");
    }

    #[test]
    fn feet_and_unknown_codes() {
        assert!(matches!(lookup(2263), Lookup::NotMetres(u) if u == "US survey foot"));
        assert!(matches!(lookup(4326), Lookup::Unknown));
        assert!(matches!(lookup(32600), Lookup::Refused(_)));
    }

    /// A CRS in feet is refused at `generate_crs`, not silently turned into a graph in feet.
    #[test]
    fn feet_crs_is_refused_at_generate_crs() {
        let text = "name: t\ncoordinate_system: wgs84\nparameters:\n  generate_crs: [1, EPSG:2263]\nlevels:\n  L1:\n    vertices:\n      - [-73.98, 40.75, 0, a]\n";
        let parsed = crate::parse_str("t.building.yaml", text);
        let d: Vec<_> = parsed
            .diagnostics
            .iter()
            .filter(|d| d.code == "E0108")
            .collect();
        assert_eq!(d.len(), 1, "{:#?}", parsed.diagnostics);
        assert_eq!(d[0].span.line, 4);
        assert!(d[0].message.contains("US survey foot"), "{}", d[0].message);
    }

    #[test]
    fn geocentric_round_trip() {
        let (a, es) = (6378137.0, 0.006694379990141317);
        let p = [0.3, 0.8, 120.0];
        let c = run(&Step::Cart { a, es, inv: false }, p, &mut vec![]).unwrap();
        let back = geodetic(a, es, c);
        assert!((back[0] - p[0]).abs() < 1e-12 && (back[1] - p[1]).abs() < 1e-12);
        assert!((back[2] - p[2]).abs() < 1e-6);
    }
}
