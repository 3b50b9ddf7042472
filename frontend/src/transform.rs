//! Coordinate systems: from file coordinates to the map frame (building_yaml.md §7).

use mapc_ir::*;

const EARTH_RADIUS: f64 = 6_378_137.0;

pub(crate) fn apply(b: &mut Building, diags: &mut Vec<Diagnostic>) {
    match b.coordinate_system {
        CoordinateSystem::ReferenceImage => reference_image(b, diags),
        CoordinateSystem::CartesianMeters => {
            b.crs_name = crs_param(b);
            b.offset = Vec2::new(
                b.params.f64("offset_x").unwrap_or(0.0),
                b.params.f64("offset_y").unwrap_or(0.0),
            );
            set_positions(b, |_, p| Some(p));
        }
        CoordinateSystem::Wgs84 => {
            b.offset = Vec2::new(
                b.params.f64("suggested_offset_x").unwrap_or(0.0),
                b.params.f64("suggested_offset_y").unwrap_or(0.0),
            );
            let Some(proj) = projector(b, diags) else {
                return;
            };
            let mut failed = None;
            set_positions(b, |span, lonlat| {
                let r = proj.lonlat(lonlat);
                if r.is_none() && failed.is_none() {
                    failed = Some(span);
                }
                r
            });
            if let Some(span) = failed {
                diags.push(
                    Diagnostic::error(
                        "E0108",
                        span,
                        "cannot project this longitude/latitude to the target CRS",
                    )
                    .with_help("wgs84 maps write x = longitude, y = latitude in degrees"),
                );
            }
        }
        CoordinateSystem::WebMercator => {
            diags.push(
                Diagnostic::warning(
                    "W0108",
                    b.spans.coordinate_system,
                    "coordinate_system web_mercator is deprecated",
                )
                .with_help("re-save the map with coordinate_system wgs84"),
            );
            let Some(proj) = projector(b, diags) else {
                return;
            };
            set_positions(b, |_, p| {
                let east = EARTH_RADIUS * std::f64::consts::PI * (p.x - 128.0) / 128.0;
                let north = EARTH_RADIUS * std::f64::consts::PI * (128.0 + p.y) / 128.0;
                proj.mercator_to_target(Vec2::new(east, north))
            });
            let origin_name = b
                .params
                .str("generate_origin_vertex")
                .unwrap_or("origin")
                .to_string();
            match b.vertices.iter().find(|(_, v)| v.name == origin_name) {
                Some((_, v)) => b.offset = v.pos,
                None => diags.push(
                    Diagnostic::warning(
                        "W0108",
                        b.spans.parameters,
                        format!(
                            "web_mercator map has no vertex named `{origin_name}`; offset is 0"
                        ),
                    )
                    .with_help("add the origin vertex or set `generate_origin_vertex`"),
                ),
            }
        }
    }
}

fn crs_param(b: &Building) -> Option<String> {
    b.params
        .str("generate_crs")
        .filter(|s| !s.is_empty())
        .map(str::to_string)
}

/// Sets every position from `f(span, file coordinates)`; elements whose projection fails
/// keep their file coordinates (an error has been reported).
fn set_positions(b: &mut Building, mut f: impl FnMut(Span, Vec2) -> Option<Vec2>) {
    let spans: Vec<Span> = b.vertices.iter().map(|(h, _)| b.vertices.span(h)).collect();
    for ((_, v), span) in b.vertices.iter_mut().zip(spans) {
        v.pos = f(span, v.raw).unwrap_or(v.raw);
    }
    let spans: Vec<Span> = b.models.iter().map(|(h, _)| b.models.span(h)).collect();
    for ((_, m), span) in b.models.iter_mut().zip(spans) {
        m.pos = f(span, m.raw).unwrap_or(m.raw);
    }
    let spans: Vec<Span> = b.lifts.iter().map(|(h, _)| b.lifts.span(h)).collect();
    for ((_, l), span) in b.lifts.iter_mut().zip(spans) {
        l.pos = f(span, l.raw).unwrap_or(l.raw);
    }
    // Fiducials of geographic maps are EPSG:3857 metres written by the editor and are not
    // used for alignment; they keep their file coordinates.
}

/// WGS 84 to the map's CRS, as PROJ does it (`crate::crs`).
struct Projector {
    target: crate::crs::Crs,
}

impl Projector {
    fn lonlat(&self, p: Vec2) -> Option<Vec2> {
        if !(-180.0..=180.0).contains(&p.x) || !(-90.0..=90.0).contains(&p.y) {
            return None;
        }
        let (e, n) = self.target.project(p.x, p.y)?;
        let out = Vec2::new(e, n);
        out.is_finite().then_some(out)
    }
    /// Legacy web_mercator files hold EPSG:3857 metres (a sphere of the WGS 84 radius):
    /// back to WGS 84 longitude/latitude, then to the target.
    fn mercator_to_target(&self, p: Vec2) -> Option<Vec2> {
        let lon = (p.x / EARTH_RADIUS).to_degrees();
        let lat =
            (2.0 * (p.y / EARTH_RADIUS).exp().atan() - std::f64::consts::FRAC_PI_2).to_degrees();
        self.lonlat(Vec2::new(lon, lat))
    }
}

fn projector(b: &mut Building, diags: &mut Vec<Diagnostic>) -> Option<Projector> {
    let cs = b.coordinate_system.as_str();
    let Some(crs) = crs_param(b) else {
        diags.push(
            Diagnostic::error(
                "E0108",
                b.spans.coordinate_system,
                format!("a {cs} map needs the building parameter `generate_crs`"),
            )
            .with_help("add `parameters: {generate_crs: [1, \"EPSG:<code>\"]}` naming the projected CRS of the site"),
        );
        return None;
    };
    b.crs_name = Some(crs.clone());
    let span = b
        .params
        .param("generate_crs")
        .map_or(b.spans.parameters, |p| p.span);
    let code = crs
        .strip_prefix("EPSG:")
        .or(crs.strip_prefix("epsg:"))
        .and_then(|c| c.trim().parse::<u32>().ok());
    let refuse = |msg: String, help: &str| Diagnostic::error("E0108", span, msg).with_help(help);
    let lookup = code.map_or(crate::crs::Lookup::Unknown, crate::crs::lookup);
    match lookup {
        crate::crs::Lookup::Crs(target) => Some(Projector { target }),
        // Refused rather than converted: the nav graph's coordinates (and the world's
        // `<crs>`) would no longer be in the CRS the map names.
        crate::crs::Lookup::NotMetres(unit) => {
            diags.push(refuse(
                format!("`generate_crs` `{crs}` is in {unit}s, not metres; nav graphs and worlds are in metres"),
                "use the metre variant of this CRS (most US State Plane zones have one, e.g. EPSG:32118 for EPSG:2263)",
            ));
            None
        }
        crate::crs::Lookup::Refused(why) => {
            diags.push(refuse(
                format!("unsupported `generate_crs` `{crs}`: {why}"),
                "use another projected CRS of the site, such as its UTM zone",
            ));
            None
        }
        crate::crs::Lookup::Unknown => {
            diags.push(refuse(
                format!("unsupported `generate_crs` `{crs}`"),
                "use an EPSG code of a projected CRS, such as EPSG:3414 or EPSG:32648",
            ));
            None
        }
    }
}

fn reference_image(b: &mut Building, diags: &mut Vec<Diagnostic>) {
    // Y flip: image rows grow downwards, the map frame's y grows upwards.
    let flip = |p: Vec2| Vec2::new(p.x, -p.y);
    let ref_level = b.reference_level;

    // Scale of the reference level: mean of distance / pixel length over its measurements.
    let mut ratios = Vec::new();
    for &mh in &b.levels[ref_level].measurements {
        let m = &b.measurements[mh];
        let len = b.vertices[m.start].raw.minus(b.vertices[m.end].raw).norm();
        if len == 0.0 || m.distance <= 0.0 {
            diags.push(
                Diagnostic::error(
                    "E0109",
                    b.measurements.span(mh),
                    if len == 0.0 {
                        "measurement has zero length, so it cannot define the scale".to_string()
                    } else {
                        format!("measurement distance must be positive, found {}", m.distance)
                    },
                )
                .with_help("draw the measurement between two distinct vertices and give its real length in metres"),
            );
            continue;
        }
        ratios.push(m.distance / len);
    }
    let s_ref = if ratios.is_empty() {
        diags.push(
            Diagnostic::warning(
                "W0106",
                b.levels.span(ref_level),
                format!(
                    "reference level `{}` has no measurement, so the map stays in pixels (scale 1)",
                    b.levels[ref_level].name
                ),
            )
            .with_help("add a measurement of known length on the reference level"),
        );
        1.0
    } else {
        ratios.iter().sum::<f64>() / ratios.len() as f64
    };

    let level_handles: Vec<Handle<Level>> = b.levels.iter().map(|(h, _)| h).collect();
    for lh in level_handles {
        let t = if lh == ref_level {
            LevelTransform {
                scale: s_ref,
                ..LevelTransform::default()
            }
        } else {
            align(b, lh, ref_level, s_ref, diags)
        };
        b.levels[lh].transform = t;
    }

    let tf = |b: &Building, l: Handle<Level>| b.levels[l].transform;
    let updates: Vec<Vec2> = b
        .vertices
        .iter()
        .map(|(_, v)| tf(b, v.level).apply(flip(v.raw)))
        .collect();
    for ((_, v), p) in b.vertices.iter_mut().zip(updates) {
        v.pos = p;
    }
    let updates: Vec<Vec2> = b
        .fiducials
        .iter()
        .map(|(_, f)| tf(b, f.level).apply(flip(f.raw)))
        .collect();
    for ((_, f), p) in b.fiducials.iter_mut().zip(updates) {
        f.pos = p;
    }
    let updates: Vec<LevelTransform> = b.models.iter().map(|(_, m)| tf(b, m.level)).collect();
    for ((_, m), t) in b.models.iter_mut().zip(updates) {
        m.pos = t.apply(flip(m.raw));
        m.yaw += t.rotation;
    }
    let updates: Vec<LevelTransform> = b
        .lifts
        .iter()
        .map(|(_, l)| tf(b, l.reference_level))
        .collect();
    for ((_, l), t) in b.lifts.iter_mut().zip(updates) {
        l.pos = t.apply(flip(l.raw));
        // The reference generator leaves lift yaw unrotated; a lift drawn on a rotated
        // level turns with it (README: differences).
        l.yaw += t.rotation;
    }
}

/// Similarity that maps `level`'s flipped pixels onto the reference level's frame using
/// fiducials with the same name.
fn align(
    b: &Building,
    lh: Handle<Level>,
    ref_level: Handle<Level>,
    s_ref: f64,
    diags: &mut Vec<Diagnostic>,
) -> LevelTransform {
    let flip = |p: Vec2| Vec2::new(p.x, -p.y);
    let mut pairs: Vec<(Vec2, Vec2)> = Vec::new();
    for &f0 in &b.levels[ref_level].fiducials {
        for &f1 in &b.levels[lh].fiducials {
            if b.fiducials[f0].name == b.fiducials[f1].name {
                pairs.push((flip(b.fiducials[f0].raw), flip(b.fiducials[f1].raw)));
            }
        }
    }
    let fallback = LevelTransform {
        scale: s_ref,
        ..LevelTransform::default()
    };
    let level = &b.levels[lh];
    if pairs.len() < 2 {
        diags.push(
            Diagnostic::warning(
                "W0107",
                b.levels.span(lh),
                format!(
                    "level `{}` shares {} fiducial(s) with the reference level `{}`; 2 are needed to align it",
                    level.name,
                    pairs.len(),
                    b.levels[ref_level].name
                ),
            )
            .with_help("add at least two fiducials with the same names on both levels; until then the level uses the reference scale without rotation or offset"),
        );
        return fallback;
    }
    let (mut sin_sum, mut cos_sum, mut k_sum, mut n) = (0.0, 0.0, 0.0, 0usize);
    for i in 0..pairs.len() {
        for j in i + 1..pairs.len() {
            let d0 = pairs[j].0.minus(pairs[i].0);
            let d1 = pairs[j].1.minus(pairs[i].1);
            if d0.norm() == 0.0 || d1.norm() == 0.0 {
                continue;
            }
            let dtheta = d1.y.atan2(d1.x) - d0.y.atan2(d0.x);
            sin_sum += dtheta.sin();
            cos_sum += dtheta.cos();
            k_sum += d1.norm() / d0.norm();
            n += 1;
        }
    }
    if n == 0 {
        diags.push(
            Diagnostic::error(
                "E0109",
                b.levels.span(lh),
                format!(
                    "the fiducials level `{}` shares with the reference level coincide, so they define no alignment",
                    level.name
                ),
            )
            .with_help("place the shared fiducials at distinct points"),
        );
        return fallback;
    }
    let theta = -sin_sum.atan2(cos_sum);
    let k = k_sum / n as f64;
    let mut t = Vec2::default();
    for (f0, f1) in &pairs {
        t = t.plus(f0.minus(f1.scale(1.0 / k).rotate(theta)));
    }
    let t = t.scale(s_ref / pairs.len() as f64);
    LevelTransform {
        scale: s_ref / k,
        rotation: theta,
        translation: t,
    }
}
