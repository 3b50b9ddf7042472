//! How a `gazebo`/`ignition`/`gz` run shares its work between two threads
//! ([`world_files_untextured`]). The documents themselves come from `world`, `doors`,
//! `lifts` and `level`; this module only decides who makes what, and in which order the
//! results are put together (the output is the same bytes as on one thread).

use super::world::{part_elements, parts, world_with, Part, WorldFiles, WorldOptions};
use super::xml::Element;
use super::Flavour;
use mapc_ir::{Building, Handle, Level};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Condvar, Mutex, OnceLock};

/// Depth of the world's models in the document (`<sdf>` 0, `<world>` 1).
const PART_DEPTH: usize = 2;

/// The level meshes (one entry per level, document order) and
/// [`super::world::world_files`] without the texture images in `models` (see
/// [`crate::level_texture_paths`]: a caller that has the images on disk links them instead
/// of holding a copy of their bytes per level). The world's element tree comes back too,
/// not freed: a caller about to exit may skip freeing it (a fifth of its cost). Its door and
/// lift models are in it as the text they were written as.
///
/// On two threads. This one builds the rest of the world's tree (thousands of small
/// allocations, which here reuse the heap the map's YAML tree freed) while a helper makes
/// the level meshes. Then both write the door and lift models, each taking the next as it
/// comes free (clinic's 119 doors are most of its world); this thread writes the world's
/// text around them, and both write the meshes' OBJ texts and each level's other files
/// the same way (airport_terminal's 70 floors are most of its work). BENCHMARKS.md has
/// the figures.
pub fn world_files_untextured(
    b: &Building,
    flavour: Flavour,
    opts: &WorldOptions,
) -> (
    Vec<(Handle<Level>, crate::LevelMeshes)>,
    WorldFiles,
    Element,
) {
    let list = parts(b);
    let shared = Shared::new(list.len());
    let next = AtomicUsize::new(0);
    // The meshes' OBJ texts (every level's, in order; the larger jobs, first), then each
    // level's other files, each taken by whoever is free.
    let work = |meshes: &[crate::LevelMeshes]| {
        let all: Vec<&crate::Mesh> = meshes.iter().flat_map(|m| m.all()).collect();
        let levels: Vec<Handle<Level>> = b.levels.iter().map(|(h, _)| h).collect();
        let mut done = Vec::new();
        loop {
            let i = next.fetch_add(1, Ordering::Relaxed);
            if let Some(m) = all.get(i) {
                done.push(Job::Obj(i, crate::mesh_obj(m, b.offset)));
            } else if let Some((&h, m)) = levels.get(i - all.len()).zip(meshes.get(i - all.len())) {
                done.push(Job::Level(i - all.len(), level_files(b, h, m)));
            } else {
                break;
            }
        }
        done
    };
    // A panic on the helper is a bug: `join` surfaces it here.
    let (theirs, (world, tree, crowd, mine)) = mapc_ir::par::join(
        || {
            // Releases the waiting thread also if the helper panics.
            let _gone = Gone(&shared);
            let meshes = b.levels.iter().map(|(h, _)| crate::level_meshes(b, h));
            let meshes = shared.publish(meshes.collect());
            shared.make_parts(b, &list, flavour);
            work(meshes)
        },
        || {
            let mut k = 0;
            let mut tree = world_with(b, flavour, opts, &mut |p| {
                debug_assert_eq!(list.get(k), Some(&p), "parts() follows world_with()");
                k += 1;
                vec![Element::verbatim(String::new())]
            });
            shared.make_parts(b, &list, flavour);
            let texts = shared.all_parts(b, &list, flavour);
            fill_parts(&mut tree, texts);
            let text = tree.to_document(false);
            let crowd = super::crowd::crowd_files(b);
            let mine = shared.meshes().map(work).unwrap_or_default();
            (text, tree, crowd, mine)
        },
    );
    let level_meshes = shared.meshes.into_inner().unwrap_or_default();
    let total = level_meshes.iter().map(|m| m.all().count()).sum();
    let mut texts: Vec<Option<String>> = vec![None; total];
    let mut files: Vec<Option<Vec<crate::OutputFile>>> = vec![None; level_meshes.len()];
    for job in theirs.into_iter().chain(mine) {
        match job {
            Job::Obj(i, t) => texts[i] = Some(t),
            Job::Level(l, f) => files[l] = Some(f),
        }
    }
    let mut texts = texts.into_iter().flatten();
    let mut meshes = Vec::new();
    let mut models = Vec::new();
    for (((h, _), m), level) in b.levels.iter().zip(level_meshes).zip(files) {
        let mut level = level.unwrap_or_else(|| level_files(b, h, &m));
        // The OBJ files, in mesh order, get their texts.
        let mut objs = texts.by_ref().take(m.all().count());
        for f in level.iter_mut().filter(|f| is_obj(&f.path)) {
            f.contents = objs.next().unwrap_or_default().into_bytes();
        }
        models.extend(level);
        meshes.push((h, m));
    }
    (
        meshes,
        WorldFiles {
            world,
            models,
            crowd,
        },
        tree,
    )
}

/// What a thread made after the meshes: a mesh's OBJ text, or a level's other files.
enum Job {
    Obj(usize, String),
    Level(usize, Vec<crate::OutputFile>),
}

/// A level model's files, its OBJ files still empty (their texts are made apart).
fn level_files(
    b: &Building,
    level: Handle<Level>,
    meshes: &crate::LevelMeshes,
) -> Vec<crate::OutputFile> {
    let empty = vec![String::new(); meshes.all().count()];
    super::level::level_model_files_with(b, level, meshes, empty)
}

fn is_obj(path: &std::path::Path) -> bool {
    path.extension().is_some_and(|e| e == "obj")
}

/// One part's models as they are written inside `<world>`.
fn part_text(b: &Building, part: Part, flavour: Flavour) -> String {
    let mut out = String::new();
    for e in part_elements(b, part, flavour) {
        e.write_at(&mut out, PART_DEPTH);
    }
    out
}

/// Puts the parts' texts into their places in the world (its verbatim children, in order).
fn fill_parts(tree: &mut Element, texts: Vec<String>) {
    let Some(world) = tree.children.iter_mut().find(|c| c.name == "world") else {
        return;
    };
    let mut texts = texts.into_iter();
    for c in world.children.iter_mut().filter(|c| c.is_verbatim()) {
        c.text = texts.next().map(Into::into);
    }
}

/// What the two threads hand each other: the level meshes (made by the helper) and the
/// parts' texts (made by both).
struct Shared {
    meshes: OnceLock<Vec<crate::LevelMeshes>>,
    next_part: AtomicUsize,
    state: Mutex<State>,
    changed: Condvar,
}

struct State {
    /// The meshes are published, or the helper ended without them.
    released: bool,
    /// The helper ended (returned or panicked).
    gone: bool,
    parts: Vec<Option<String>>,
}

impl Shared {
    fn new(parts: usize) -> Shared {
        Shared {
            meshes: OnceLock::new(),
            next_part: AtomicUsize::new(0),
            state: Mutex::new(State {
                released: false,
                gone: false,
                parts: vec![None; parts],
            }),
            changed: Condvar::new(),
        }
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, State> {
        self.state.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// Stores the meshes, wakes the waiter and gives them back.
    fn publish(&self, meshes: Vec<crate::LevelMeshes>) -> &[crate::LevelMeshes] {
        let _ = self.meshes.set(meshes);
        self.lock().released = true;
        self.changed.notify_all();
        self.meshes.get().map_or(&[], Vec::as_slice)
    }

    /// The meshes once published; `None` when the helper ended without them (a panic).
    fn meshes(&self) -> Option<&[crate::LevelMeshes]> {
        let mut s = self.lock();
        while !s.released {
            s = self.changed.wait(s).unwrap_or_else(|e| e.into_inner());
        }
        drop(s);
        self.meshes.get().map(Vec::as_slice)
    }

    /// Makes parts, the next one not taken each time, until none is left.
    fn make_parts(&self, b: &Building, list: &[Part], flavour: Flavour) {
        loop {
            let i = self.next_part.fetch_add(1, Ordering::Relaxed);
            let Some(&p) = list.get(i) else { return };
            let text = part_text(b, p, flavour);
            self.lock().parts[i] = Some(text);
            self.changed.notify_all();
        }
    }

    /// Every part's text, in order: waits for those the helper is making, and makes any it
    /// left unfinished (it panicked) here.
    fn all_parts(&self, b: &Building, list: &[Part], flavour: Flavour) -> Vec<String> {
        let mut s = self.lock();
        while !s.gone && s.parts.iter().any(Option::is_none) {
            s = self.changed.wait(s).unwrap_or_else(|e| e.into_inner());
        }
        let parts = std::mem::take(&mut s.parts);
        drop(s);
        parts
            .into_iter()
            .zip(list)
            .map(|(t, &p)| t.unwrap_or_else(|| part_text(b, p, flavour)))
            .collect()
    }
}

/// Marks the helper ended when dropped, whatever happened, and wakes the waiter.
struct Gone<'a>(&'a Shared);

impl Drop for Gone<'_> {
    fn drop(&mut self) {
        let mut s = self.0.lock();
        s.released = true;
        s.gone = true;
        drop(s);
        self.0.changed.notify_all();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The waiting thread gets the meshes, or is let go when the helper ends without them
    /// (a panic) rather than waiting forever.
    #[test]
    fn the_meshes_are_handed_over_or_the_waiter_released() {
        let shared = Shared::new(0);
        let got = mapc_ir::par::join(
            || {
                let _gone = Gone(&shared);
                shared.publish(vec![crate::LevelMeshes::default()]).len()
            },
            || shared.meshes().map(<[_]>::len),
        );
        assert_eq!(got, (1, Some(1)));
        let shared = Shared::new(0);
        let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            mapc_ir::par::join(
                || {
                    let _gone = Gone(&shared);
                    panic!("making the meshes failed")
                },
                || shared.meshes().is_none(),
            )
        }));
        assert!(r.is_err());
        assert!(shared.meshes().is_none());
    }

    /// Two sliding doors on one level, a wall beside each (a level mesh, so the level has
    /// OBJ files), no lift.
    fn building() -> Building {
        use mapc_ir::{Door, DoorKind, MotionAxis, Params, Span};
        let mut m = crate::geometry::tests::Map::new();
        for (k, x) in [0.0, 5.0].into_iter().enumerate() {
            let (start, end) = (m.v(x, 0.0), m.v(x + 1.0, 0.0));
            let d = m.b.doors.append(
                Door {
                    level: m.level,
                    start,
                    end,
                    name: format!("door_{k}"),
                    kind: DoorKind::parse("sliding"),
                    motion_axis: MotionAxis::Start,
                    motion_direction: 1,
                    motion_degrees: 90.0,
                    right_left_ratio: 1.0,
                    plugin: true,
                    params: Params::default(),
                },
                Span::default(),
            );
            m.b.levels[m.level].doors.push(d);
            m.wall((x, 0.0), (x, 3.0), Vec::new());
        }
        m.b
    }

    /// On two threads the world is the same bytes as on one, its doors in place.
    #[test]
    fn the_world_is_the_one_thread_world() {
        let b = building();
        for f in [Flavour::Gz, Flavour::Ignition, Flavour::Classic] {
            let opts = WorldOptions::default();
            let (meshes, files, _) = world_files_untextured(&b, f, &opts);
            assert_eq!(files.world, super::super::world::world_text(&b, f, &opts));
            // The level models too: the same files in the same order.
            let one: Vec<_> = meshes
                .iter()
                .flat_map(|(h, m)| {
                    let objs = m.all().map(|x| crate::mesh_obj(x, b.offset)).collect();
                    super::super::level::level_model_files_with(&b, *h, m, objs)
                })
                .collect();
            assert!(files
                .models
                .iter()
                .any(|f| is_obj(&f.path) && !f.contents.is_empty()));
            assert_eq!(files.models, one);
            for d in ["door_0", "door_1"] {
                // The model, and its name in the floor toggle.
                assert_eq!(
                    files
                        .world
                        .matches(&format!("<model name=\"{d}\">"))
                        .count(),
                    1
                );
                assert_eq!(
                    files
                        .world
                        .matches(&format!("<model name=\"{d}\" />"))
                        .count(),
                    1
                );
            }
        }
    }

    /// A part the helper took and did not finish (it panicked) is made by the waiter, so
    /// it neither hangs nor loses the part.
    #[test]
    fn parts_left_by_a_failed_helper_are_made_by_the_waiter() {
        let b = building();
        let list = parts(&b);
        assert_eq!(list.len(), 2);
        let shared = Shared::new(2);
        // The helper took both parts, made the second one and ended.
        shared.next_part.store(2, Ordering::Relaxed);
        shared.lock().parts[1] = Some("made\n".into());
        drop(Gone(&shared));
        let texts = shared.all_parts(&b, &list, Flavour::Gz);
        assert!(
            texts[0].starts_with("    <model name=\"door_0\">\n"),
            "{}",
            texts[0]
        );
        assert_eq!(texts[0], part_text(&b, list[0], Flavour::Gz));
        assert_eq!(texts[1], "made\n");
    }
}
