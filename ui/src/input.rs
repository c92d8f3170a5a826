//! Input apart from drawing: the keyboard's shortcuts and the mouse in the 3D view
//! (camera on the right and middle buttons, the tool on the left) become `Action`s; only
//! the camera and the drag in progress change here.

use glam::Vec2;
use shared::sim_to_ui::tool;

use crate::action::{Action, PathOp};
use crate::camera::{Camera, Hit, pick};
use crate::panels::{Drag, ViewPanel};
use crate::store::Store;
use crate::tools::TOOLS;

/// The keyboard's shortcuts: a tool's key, undo, redo, save, home, F (frame the scene),
/// M (the map: the threads' stretch or the ease), Space (pause or simulate).
pub fn keyboard(ctx: &egui::Context, save_path: &str, actions: &mut Vec<Action>) {
    if ctx.egui_wants_keyboard_input() {
        return;
    }
    let (mut tool_key, mut undo, mut redo, mut save, mut home, mut frame, mut map) =
        (None, false, false, false, false, false, false);
    let mut pause = false;
    ctx.input(|i| {
        for (t, _, key, _) in TOOLS {
            if i.key_pressed(key) && !i.modifiers.command {
                tool_key = Some(t);
            }
        }
        undo = i.modifiers.command && i.key_pressed(egui::Key::Z) && !i.modifiers.shift;
        redo = i.modifiers.command
            && (i.key_pressed(egui::Key::Y) || (i.modifiers.shift && i.key_pressed(egui::Key::Z)));
        save = i.modifiers.command && i.key_pressed(egui::Key::S);
        home = i.key_pressed(egui::Key::Home);
        frame = i.key_pressed(egui::Key::F) && !i.modifiers.command;
        map = i.key_pressed(egui::Key::M) && !i.modifiers.command;
        pause = i.key_pressed(egui::Key::Space) && !i.modifiers.command;
    });
    if save {
        actions.push(Action::Path(PathOp::Save, save_path.to_string()));
    } else if let Some(t) = tool_key {
        actions.push(Action::SetTool(t));
    }
    if undo {
        actions.push(Action::Command(shared::command::Command::Undo));
    }
    if redo {
        actions.push(Action::Command(shared::command::Command::Redo));
    }
    if home {
        actions.push(Action::ResetCamera);
    }
    if frame {
        actions.push(Action::FrameScene);
    }
    if map {
        actions.push(Action::ToggleStretchMap);
    }
    // A focused button takes Space as a click of its own.
    if pause && ctx.memory(|m| m.focused()).is_none() {
        actions.push(Action::ToggleSimulating);
    }
}

/// The mouse in the 3D view with tool `t`; with `darting` (the dart's width at the edge,
/// m) a primary drag takes in a dart instead ([`dart_drag`]).
#[allow(clippy::too_many_arguments)]
pub fn view_mouse(
    view: &mut ViewPanel,
    camera: &mut Camera,
    store: &Store,
    t: u32,
    darting: Option<f32>,
    resp: &egui::Response,
    ctx: &egui::Context,
    actions: &mut Vec<Action>,
) {
    let rect = resp.rect;
    let size = Vec2::new(rect.width(), rect.height());
    let shift = camera_mouse(camera, size, resp, ctx);
    let Some(pos) = resp.interact_pointer_pos().or(resp.hover_pos()) else {
        return;
    };
    let local = Vec2::new(pos.x - rect.min.x, pos.y - rect.min.y);
    let (o, dir, hit) = ray_hit(camera, store, size, local);
    if resp.hovered() {
        view.last_hit = hit;
    }
    if let Some(width_m) = darting {
        // Where the button went down, picked once, as the drag starts.
        let start = (resp.drag_started_by(egui::PointerButton::Primary))
            .then(|| ray_hit(camera, store, size, press_origin(ctx, rect)?).2)
            .flatten();
        dart_drag(view, store, (start, hit), width_m, resp, ctx, actions);
        return;
    }
    let primary_pressed = resp.drag_started_by(egui::PointerButton::Primary)
        || resp.clicked_by(egui::PointerButton::Primary);
    // A drag with pinch, tear or a cut stroke moves the simulated pen, button held.
    let pen_tool = matches!(t, tool::PINCH | tool::TEAR | tool::CUT | tool::PAINT);
    // Scissors and brush may start beside the cloth, as scissors start beside the fabric
    // to cut across it: the stroke begins where it meets the cloth.
    let from_beside = matches!(t, tool::CUT | tool::PAINT);
    if resp.drag_started_by(egui::PointerButton::Primary) && pen_tool {
        // The drag begins where the button went down: a slow frame (the software
        // renderer at 2 fps under load) sees it start a long mouse step later, off the
        // cloth ("nothing under the mouse") or on another part of it.
        let from = press_origin(ctx, rect).unwrap_or(local);
        let (o, dir, hit) = ray_hit(camera, store, size, from);
        if let Some(h) = hit {
            let depth = (h.point - o).dot(dir);
            view.drag = Some(Drag { depth, pen: true });
            actions.push(Action::Pointer(h.point.to_array(), 1));
        } else if from_beside {
            view.stroke_from = Some(from);
        } else {
            actions.push(Action::Status(format!(
                "{}: nothing under the mouse to grab; point at the cloth",
                crate::tools::tool_name(t)
            )));
        }
    } else if let Some(from) = view.stroke_from {
        if !resp.dragged_by(egui::PointerButton::Primary) {
            view.stroke_from = None;
            actions.push(Action::Status(format!(
                "{}: the stroke never crossed the cloth",
                crate::tools::tool_name(t)
            )));
        } else if let Some(h) = hit {
            // Scissors go down just beside the cloth's border, so that the cut starts
            // across it rather than a mouse step inside; the brush where it met the cloth
            // (beside it, its dab would go to the nearest cloth, wherever that is).
            let start = if t == tool::CUT {
                border_point(camera, store, size, from, local)
                    .map(|b| b + (b - h.point).normalize_or_zero() * BESIDE_M)
                    .unwrap_or(h.point)
            } else {
                h.point
            };
            let depth = (h.point - o).dot(dir);
            view.drag = Some(Drag { depth, pen: true });
            view.stroke_from = None;
            actions.push(Action::Pointer(start.to_array(), 1));
            if start != h.point {
                actions.push(Action::Pointer(h.point.to_array(), 1));
            }
        } else {
            view.stroke_from = Some(local);
        }
    } else if let Some(dr) = &mut view.drag {
        // Scissors and brush ride the cloth under the mouse (a stroke at the press's
        // depth left a round torso within a few centimetres, and the cut stopped
        // there); pinch and tear keep that depth, and the cloth follows the pen.
        let target = match hit {
            Some(h) if matches!(t, tool::CUT | tool::PAINT) => {
                dr.depth = (h.point - o).dot(dir);
                h.point
            }
            _ => o + dir * dr.depth,
        };
        if resp.dragged_by(egui::PointerButton::Primary) {
            if dr.pen {
                actions.push(Action::Pointer(target.to_array(), 1));
            }
        } else if resp.drag_stopped() || !ctx.input(|i| i.pointer.primary_down()) {
            actions.push(Action::Pointer(target.to_array(), 0));
            view.drag = None;
        }
    }
    if resp.clicked_by(egui::PointerButton::Primary) && primary_pressed {
        // A shift-click with Pin frees the pin drawn under the mouse, not the cloth's vertex.
        let pin = (t == tool::PIN && shift).then(|| pin_under(camera, store, size, local));
        let hit = pin.flatten().or(hit);
        actions.push(Action::Click {
            tool: t,
            hit,
            shift,
            view_dir: dir,
        });
    }
}

/// Where the primary button went down, in view pixels from `rect`'s corner.
fn press_origin(ctx: &egui::Context, rect: egui::Rect) -> Option<Vec2> {
    let p = ctx.input(|i| i.pointer.press_origin())?;
    Some(Vec2::new(p.x - rect.min.x, p.y - rect.min.y))
}

/// The camera on the wheel (zoom), the middle button or shift and the right (pan) and
/// the right button (orbit), in a view of `size` pixels; returns whether shift is held.
fn camera_mouse(
    camera: &mut Camera,
    size: Vec2,
    resp: &egui::Response,
    ctx: &egui::Context,
) -> bool {
    let (shift, wheel) = ctx.input(|i| (i.modifiers.shift, i.smooth_scroll_delta.y));
    if resp.hovered() && wheel != 0.0 {
        camera.zoom(wheel / 50.0);
    }
    let d = resp.drag_delta();
    let dv = Vec2::new(d.x, d.y);
    if resp.dragged_by(egui::PointerButton::Middle)
        || (resp.dragged_by(egui::PointerButton::Secondary) && shift)
    {
        camera.pan(dv, size.y);
    } else if resp.dragged_by(egui::PointerButton::Secondary) {
        camera.orbit(dv);
    }
    shift
}

/// A dart dragged on the cloth in the 3D view, as a designer takes one in on the form:
/// from the dart's point (where the button went down, `hits.0`) out past the piece's
/// edge. The drag's way is followed in the pattern plane through the places it crosses
/// on the same piece (`hits.1` under the mouse now); let go off that piece, the dart's
/// line runs on past the last of them by a quarter of its length (at least 3 cm), so
/// that it leaves the piece there, and goes to cloth-sim as a DART_PLANE of `width_m`.
/// Let go on the piece, it ends there (and cloth-sim says the line does not leave it).
fn dart_drag(
    view: &mut ViewPanel,
    store: &Store,
    hits: (Option<Hit>, Option<Hit>),
    width_m: f32,
    resp: &egui::Response,
    ctx: &egui::Context,
    actions: &mut Vec<Action>,
) {
    let piece = |h: &Hit| {
        let (_, k) = h.place?;
        store.mesh.as_ref()?.piece_of.get(&k).copied()
    };
    if resp.drag_started_by(egui::PointerButton::Primary) {
        view.dart = hits.0.and_then(|h| {
            let (p, _) = h.place?;
            Some(crate::panels::DartDrag {
                from: p,
                last: p,
                piece: piece(&h),
                start: h.point.to_array(),
                now: h.point.to_array(),
            })
        });
        actions.push(Action::Status(
            match view.dart {
                Some(_) => "Dart: drag out past the piece's edge and let go",
                None => "Dart: start the drag on the cloth, at the dart's point",
            }
            .into(),
        ));
        return;
    }
    let Some(mut d) = view.dart else {
        return;
    };
    let on_piece = hits.1.filter(|h| piece(h) == d.piece).and_then(|h| h.place);
    if resp.dragged_by(egui::PointerButton::Primary) {
        if let Some((p, _)) = on_piece {
            d.last = p;
        }
        if let Some(h) = hits.1 {
            d.now = h.point.to_array();
        }
        view.dart = Some(d);
        return;
    }
    if !resp.drag_stopped() && ctx.input(|i| i.pointer.primary_down()) {
        return;
    }
    let (from, last) = (glam::Vec2::from(d.from), glam::Vec2::from(d.last));
    view.dart = None;
    let toward = match on_piece {
        Some((p, _)) => glam::Vec2::from(p),
        None => {
            let way = last - from;
            last + way.normalize_or_zero() * (0.25 * way.length()).max(0.03)
        }
    };
    if toward.distance(from) < 1e-3 {
        actions.push(Action::Status(
            "Dart: drag from the dart's point out past the piece's edge".into(),
        ));
        return;
    }
    actions.push(Action::Command(shared::command::Command::DartPlane {
        point: d.from,
        toward: toward.to_array(),
        width_m,
    }));
}

/// The pin whose drawing (its shaft and head) passes nearest view point `at` (pixels from
/// the view's corner), within 12 of them, as a hit at its vertex.
fn pin_under(camera: &Camera, store: &Store, size: Vec2, at: Vec2) -> Option<crate::camera::Hit> {
    let eye = camera.eye();
    (store.pins.iter())
        .filter_map(|&v| {
            let (p, head, _) = crate::view3d::pin_head(store, v, eye)?;
            let (a, b) = (camera.to_screen(p, size)?, camera.to_screen(head, size)?);
            let ab = b - a;
            let t = ((at - a).dot(ab) / ab.length_squared().max(1e-6)).clamp(0.0, 1.0);
            let d = at.distance(a + ab * t);
            (d <= 12.0).then_some((d, v, p))
        })
        .min_by(|x, y| x.0.total_cmp(&y.0))
        .map(|(_, vertex, point)| crate::camera::Hit {
            point,
            vertex,
            distance: point.distance(eye),
            place: None,
        })
}

/// How far beside the border a stroke begun beside the cloth puts the pen down, along
/// the stroke (cloth-sim takes a stroke's points within 2 cm to the cloth's surface), m.
const BESIDE_M: f32 = 0.003;

/// The ray through view point `p` (its origin and direction) and where it meets the
/// cloth.
fn ray_hit(
    camera: &Camera,
    store: &Store,
    size: Vec2,
    p: Vec2,
) -> (glam::Vec3, glam::Vec3, Option<crate::camera::Hit>) {
    let (o, dir) = camera.ray(p, size);
    let hit = (store.mesh.as_ref()).and_then(|m| pick(o, dir, &m.corners, &store.x));
    (o, dir, hit)
}

/// Where on the cloth the screen segment from `off` (beside the cloth) to `on` (over it)
/// first meets it, to a tenth of a pixel: where a stroke begun beside the cloth crosses
/// its border.
fn border_point(
    camera: &Camera,
    store: &Store,
    size: Vec2,
    off: Vec2,
    on: Vec2,
) -> Option<glam::Vec3> {
    let mesh = store.mesh.as_ref()?;
    let hit = |p: Vec2| {
        let (o, dir) = camera.ray(p, size);
        pick(o, dir, &mesh.corners, &store.x).map(|h| h.point)
    };
    let (mut off, mut on, mut point) = (off, on, hit(on)?);
    while off.distance(on) > 0.1 {
        let mid = 0.5 * (off + on);
        match hit(mid) {
            Some(p) => (on, point) = (mid, p),
            None => off = mid,
        }
    }
    Some(point)
}
