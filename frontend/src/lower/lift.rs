//! A lift: its cabin, doors and the levels it serves.

use super::*;

impl Lower<'_> {
    pub(super) fn lift(&mut self, b: &Building, name: &str, node: &Node) -> Option<Lift> {
        let what = format!("lift `{name}`");
        self.map(node, &what)?;
        let x = self.req_f64(node, "x", &what);
        let y = self.req_f64(node, "y", &what);
        let yaw = self.req_f64(node, "yaw", &what);
        let width = self.req_f64(node, "width", &what);
        let depth = self.req_f64(node, "depth", &what);
        let level_opt = |l: &mut Self, key: &str| -> Option<Handle<Level>> {
            let n = node.get(key)?;
            if n.is_null() || n.key_text() == Some("") {
                return None;
            }
            l.level_ref(b, n, &format!("{what} `{key}`"))
        };
        let reference_level = level_opt(self, "reference_floor_name").unwrap_or(b.reference_level);
        let initial_level = level_opt(self, "initial_floor_name");
        let lowest_level = level_opt(self, "lowest_floor");
        let highest_level = level_opt(self, "highest_floor");
        let plugins = self.opt_bool(node, "plugins", &what, true);

        let mut doors = Vec::new();
        if let Some(d) = node.get("doors") {
            for (k, v) in self.map(d, &format!("the doors of {what}")).unwrap_or(&[]) {
                let dname = k.key_text().unwrap_or_default().to_string();
                let dwhat = format!("lift door `{dname}`");
                if self.map(v, &dwhat).is_none() {
                    continue;
                }
                let door_type = self
                    .require(v, "door_type", &dwhat)
                    .and_then(|n| self.i64(n, "`door_type`"));
                let dx = self.req_f64(v, "x", &dwhat);
                let dy = self.req_f64(v, "y", &dwhat);
                let dw = self.req_f64(v, "width", &dwhat);
                let mao = self.req_f64(v, "motion_axis_orientation", &dwhat);
                if let (Some(door_type), Some(dx), Some(dy), Some(width), Some(mao)) =
                    (door_type, dx, dy, dw, mao)
                {
                    doors.push(LiftDoor {
                        name: dname,
                        door_type,
                        pos: Vec2::new(dx, dy),
                        width,
                        motion_axis_orientation: mao,
                        span: k.span,
                    });
                }
            }
        }
        let mut level_doors = Vec::new();
        if let Some(ld) = node.get("level_doors") {
            for (k, v) in self
                .map(ld, &format!("the level_doors of {what}"))
                .unwrap_or(&[])
            {
                let Some(level) = self.level_ref(b, k, &format!("a level_doors key of {what}"))
                else {
                    continue;
                };
                let names = self
                    .seq(v, "a level_doors entry")
                    .unwrap_or(&[])
                    .iter()
                    .filter_map(|n| self.string(n, "a lift door name").map(|s| (s, n.span)))
                    .collect();
                level_doors.push(LevelDoors {
                    level,
                    doors: names,
                    span: k.span,
                });
            }
        }
        let raw = Vec2::new(x?, y?);
        Some(Lift {
            name: name.to_string(),
            pos: raw,
            raw,
            yaw: yaw?,
            width: width?,
            depth: depth?,
            reference_level,
            initial_level,
            lowest_level,
            highest_level,
            plugins,
            doors,
            level_doors,
        })
    }
}
