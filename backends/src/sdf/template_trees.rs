//! The default world templates (`templates/*.sdf`) as trees: made by the test
//! `sdf::world::tests::template_trees_are_current` from `parse_template`'s reading
//! of them. Do not edit; change the template and run that test.

use super::xml::Element;

fn e(
    name: &'static str,
    attrs: &[(&'static str, &'static str)],
    text: Option<&'static str>,
    children: Vec<Element>,
) -> Element {
    Element {
        name: name.into(),
        attrs: attrs.iter().map(|&(k, v)| (k.into(), v.into())).collect(),
        children,
        text: text.map(Into::into),
    }
}

pub(super) fn gz() -> Element {
    e("sdf", &[("version", "1.7")], None, vec![
        e("world", &[("name", "sim_world")], None, vec![
            e("physics", &[("name", "10ms"), ("type", "ode")], None, vec![
                e("max_step_size", &[], Some("0.01"), vec![]),
                e("real_time_factor", &[], Some("1.0"), vec![]),
            ]),
            e("plugin", &[("filename", "libdoor.so"), ("name", "door")], Some("\n    "), vec![]),
            e("plugin", &[("filename", "liblift.so"), ("name", "lift")], Some("\n    "), vec![]),
            e("scene", &[], None, vec![
                e("ambient", &[], Some("1 1 1"), vec![]),
                e("background", &[], Some("0.8 0.8 0.8"), vec![]),
                e("grid", &[], Some("false"), vec![]),
            ]),
            e("gui", &[("fullscreen", "0")], None, vec![
                e("window", &[], None, vec![
                    e("width", &[], Some("1000"), vec![]),
                    e("height", &[], Some("845"), vec![]),
                    e("style", &[("material_theme", "Light"), ("material_primary", "DeepOrange"), ("material_accent", "LightBlue"), ("toolbar_color_light", "#f3f3f3"), ("toolbar_text_color_light", "#111111"), ("toolbar_color_dark", "#414141"), ("toolbar_text_color_dark", "#f3f3f3"), ("plugin_toolbar_color_light", "#bbdefb"), ("plugin_toolbar_text_color_light", "#111111"), ("plugin_toolbar_color_dark", "#607d8b"), ("plugin_toolbar_text_color_dark", "#eeeeee")], None, vec![]),
                    e("menus", &[], None, vec![
                        e("drawer", &[("default", "false")], Some("\n          "), vec![]),
                    ]),
                ]),
                e("plugin", &[("filename", "MinimalScene"), ("name", "3D View")], None, vec![
                    e("gz-gui", &[], None, vec![
                        e("title", &[], Some("3D View"), vec![]),
                        e("property", &[("type", "bool"), ("key", "showTitleBar")], Some("false"), vec![]),
                        e("property", &[("type", "string"), ("key", "state")], Some("docked"), vec![]),
                    ]),
                    e("engine", &[], Some("ogre2"), vec![]),
                    e("scene", &[], Some("scene"), vec![]),
                    e("ambient_light", &[], Some("0.4 0.4 0.4"), vec![]),
                    e("background_color", &[], Some("0.8 0.8 0.8"), vec![]),
                    e("camera_pose", &[], Some("-6 0 6 0 0.5 0"), vec![]),
                ]),
                e("plugin", &[("filename", "MarkerManager"), ("name", "Marker manager")], None, vec![
                    e("gz-gui", &[], None, vec![
                        e("property", &[("key", "resizable"), ("type", "bool")], Some("false"), vec![]),
                        e("property", &[("key", "width"), ("type", "double")], Some("5"), vec![]),
                        e("property", &[("key", "height"), ("type", "double")], Some("5"), vec![]),
                        e("property", &[("key", "state"), ("type", "string")], Some("floating"), vec![]),
                        e("property", &[("key", "showTitleBar"), ("type", "bool")], Some("false"), vec![]),
                    ]),
                ]),
                e("plugin", &[("filename", "SelectEntities"), ("name", "Select Entities")], None, vec![
                    e("gz-gui", &[], None, vec![
                        e("property", &[("key", "resizable"), ("type", "bool")], Some("false"), vec![]),
                        e("property", &[("key", "width"), ("type", "double")], Some("5"), vec![]),
                        e("property", &[("key", "height"), ("type", "double")], Some("5"), vec![]),
                        e("property", &[("key", "state"), ("type", "string")], Some("floating"), vec![]),
                        e("property", &[("key", "showTitleBar"), ("type", "bool")], Some("false"), vec![]),
                    ]),
                ]),
                e("plugin", &[("filename", "Spawn"), ("name", "Spawn Entities")], None, vec![
                    e("gz-gui", &[], None, vec![
                        e("property", &[("key", "resizable"), ("type", "bool")], Some("false"), vec![]),
                        e("property", &[("key", "width"), ("type", "double")], Some("5"), vec![]),
                        e("property", &[("key", "height"), ("type", "double")], Some("5"), vec![]),
                        e("property", &[("key", "state"), ("type", "string")], Some("floating"), vec![]),
                        e("property", &[("key", "showTitleBar"), ("type", "bool")], Some("false"), vec![]),
                    ]),
                ]),
                e("plugin", &[("filename", "VisualizationCapabilities"), ("name", "Visualization Capabilities")], None, vec![
                    e("gz-gui", &[], None, vec![
                        e("property", &[("key", "resizable"), ("type", "bool")], Some("false"), vec![]),
                        e("property", &[("key", "width"), ("type", "double")], Some("5"), vec![]),
                        e("property", &[("key", "height"), ("type", "double")], Some("5"), vec![]),
                        e("property", &[("key", "state"), ("type", "string")], Some("floating"), vec![]),
                        e("property", &[("key", "showTitleBar"), ("type", "bool")], Some("false"), vec![]),
                    ]),
                ]),
                e("plugin", &[("filename", "Shapes"), ("name", "Shapes")], None, vec![
                    e("gz-gui", &[], None, vec![
                        e("property", &[("key", "resizable"), ("type", "bool")], Some("false"), vec![]),
                        e("property", &[("key", "x"), ("type", "double")], Some("0"), vec![]),
                        e("property", &[("key", "y"), ("type", "double")], Some("0"), vec![]),
                        e("property", &[("key", "width"), ("type", "double")], Some("250"), vec![]),
                        e("property", &[("key", "height"), ("type", "double")], Some("50"), vec![]),
                        e("property", &[("key", "state"), ("type", "string")], Some("floating"), vec![]),
                        e("property", &[("key", "showTitleBar"), ("type", "bool")], Some("false"), vec![]),
                        e("property", &[("key", "cardBackground"), ("type", "string")], Some("#666666"), vec![]),
                    ]),
                ]),
                e("plugin", &[("filename", "Lights"), ("name", "Lights")], None, vec![
                    e("gz-gui", &[], None, vec![
                        e("property", &[("key", "resizable"), ("type", "bool")], Some("false"), vec![]),
                        e("property", &[("key", "x"), ("type", "double")], Some("250"), vec![]),
                        e("property", &[("key", "y"), ("type", "double")], Some("0"), vec![]),
                        e("property", &[("key", "width"), ("type", "double")], Some("150"), vec![]),
                        e("property", &[("key", "height"), ("type", "double")], Some("50"), vec![]),
                        e("property", &[("key", "state"), ("type", "string")], Some("floating"), vec![]),
                        e("property", &[("key", "showTitleBar"), ("type", "bool")], Some("false"), vec![]),
                        e("property", &[("key", "cardBackground"), ("type", "string")], Some("#666666"), vec![]),
                    ]),
                ]),
                e("plugin", &[("filename", "TransformControl"), ("name", "Transform control")], None, vec![
                    e("gz-gui", &[], None, vec![
                        e("property", &[("key", "resizable"), ("type", "bool")], Some("false"), vec![]),
                        e("property", &[("key", "x"), ("type", "double")], Some("0"), vec![]),
                        e("property", &[("key", "y"), ("type", "double")], Some("50"), vec![]),
                        e("property", &[("key", "width"), ("type", "double")], Some("250"), vec![]),
                        e("property", &[("key", "height"), ("type", "double")], Some("50"), vec![]),
                        e("property", &[("key", "state"), ("type", "string")], Some("floating"), vec![]),
                        e("property", &[("key", "showTitleBar"), ("type", "bool")], Some("false"), vec![]),
                        e("property", &[("key", "cardBackground"), ("type", "string")], Some("#777777"), vec![]),
                    ]),
                ]),
                e("plugin", &[("filename", "Screenshot"), ("name", "Screenshot")], None, vec![
                    e("gz-gui", &[], None, vec![
                        e("property", &[("key", "resizable"), ("type", "bool")], Some("false"), vec![]),
                        e("property", &[("key", "x"), ("type", "double")], Some("250"), vec![]),
                        e("property", &[("key", "y"), ("type", "double")], Some("50"), vec![]),
                        e("property", &[("key", "width"), ("type", "double")], Some("50"), vec![]),
                        e("property", &[("key", "height"), ("type", "double")], Some("50"), vec![]),
                        e("property", &[("key", "state"), ("type", "string")], Some("floating"), vec![]),
                        e("property", &[("key", "showTitleBar"), ("type", "bool")], Some("false"), vec![]),
                        e("property", &[("key", "cardBackground"), ("type", "string")], Some("#777777"), vec![]),
                    ]),
                ]),
                e("plugin", &[("filename", "CopyPaste"), ("name", "CopyPaste")], None, vec![
                    e("gz-gui", &[], None, vec![
                        e("property", &[("key", "resizable"), ("type", "bool")], Some("false"), vec![]),
                        e("property", &[("key", "x"), ("type", "double")], Some("300"), vec![]),
                        e("property", &[("key", "y"), ("type", "double")], Some("50"), vec![]),
                        e("property", &[("key", "width"), ("type", "double")], Some("100"), vec![]),
                        e("property", &[("key", "height"), ("type", "double")], Some("50"), vec![]),
                        e("property", &[("key", "state"), ("type", "string")], Some("floating"), vec![]),
                        e("property", &[("key", "showTitleBar"), ("type", "bool")], Some("false"), vec![]),
                        e("property", &[("key", "cardBackground"), ("type", "string")], Some("#777777"), vec![]),
                    ]),
                ]),
                e("plugin", &[("filename", "ComponentInspector"), ("name", "Component inspector")], None, vec![
                    e("gz-gui", &[], None, vec![
                        e("property", &[("type", "bool"), ("key", "showTitleBar")], Some("false"), vec![]),
                        e("property", &[("type", "string"), ("key", "state")], Some("docked"), vec![]),
                    ]),
                ]),
                e("plugin", &[("filename", "EntityTree"), ("name", "Entity tree")], None, vec![
                    e("gz-gui", &[], None, vec![
                        e("property", &[("type", "bool"), ("key", "showTitleBar")], Some("false"), vec![]),
                        e("property", &[("type", "string"), ("key", "state")], Some("docked"), vec![]),
                    ]),
                ]),
                e("plugin", &[("filename", "toggle_charging"), ("name", "toggle_charging")], None, vec![]),
            ]),
            e("light", &[("type", "directional"), ("name", "sun")], None, vec![
                e("cast_shadows", &[], Some("true"), vec![]),
                e("pose", &[], Some("0 0 10 0 0 0"), vec![]),
                e("diffuse", &[], Some("1 1 1 1"), vec![]),
                e("specular", &[], Some("0.2 0.2 0.2 1"), vec![]),
                e("attenuation", &[], None, vec![
                    e("range", &[], Some("1000"), vec![]),
                    e("constant", &[], Some("0.09"), vec![]),
                    e("linear", &[], Some("0.001"), vec![]),
                    e("quadratic", &[], Some("0.001"), vec![]),
                ]),
                e("direction", &[], Some("-0.5 0.1 -0.9"), vec![]),
            ]),
        ]),
    ])
}

pub(super) fn ignition() -> Element {
    e("sdf", &[("version", "1.7")], None, vec![
        e("world", &[("name", "sim_world")], None, vec![
            e("physics", &[("name", "10ms"), ("type", "ode")], None, vec![
                e("max_step_size", &[], Some("0.01"), vec![]),
                e("real_time_factor", &[], Some("1.0"), vec![]),
            ]),
            e("plugin", &[("filename", "libignition-gazebo-physics-system.so"), ("name", "ignition::gazebo::systems::Physics")], Some("\n    "), vec![]),
            e("plugin", &[("filename", "libignition-gazebo-user-commands-system.so"), ("name", "ignition::gazebo::systems::UserCommands")], Some("\n    "), vec![]),
            e("plugin", &[("filename", "libignition-gazebo-scene-broadcaster-system.so"), ("name", "ignition::gazebo::systems::SceneBroadcaster")], Some("\n    "), vec![]),
            e("scene", &[], None, vec![
                e("ambient", &[], Some("1 1 1"), vec![]),
                e("background", &[], Some("0.8 0.8 0.8"), vec![]),
                e("grid", &[], Some("false"), vec![]),
            ]),
            e("gui", &[("fullscreen", "0")], None, vec![
                e("window", &[], None, vec![
                    e("width", &[], Some("1000"), vec![]),
                    e("height", &[], Some("845"), vec![]),
                    e("style", &[("material_theme", "Light"), ("material_primary", "DeepOrange"), ("material_accent", "LightBlue"), ("toolbar_color_light", "#f3f3f3"), ("toolbar_text_color_light", "#111111"), ("toolbar_color_dark", "#414141"), ("toolbar_text_color_dark", "#f3f3f3"), ("plugin_toolbar_color_light", "#bbdefb"), ("plugin_toolbar_text_color_light", "#111111"), ("plugin_toolbar_color_dark", "#607d8b"), ("plugin_toolbar_text_color_dark", "#eeeeee")], None, vec![]),
                    e("menus", &[], None, vec![
                        e("drawer", &[("default", "false")], Some("\n          "), vec![]),
                    ]),
                ]),
                e("plugin", &[("filename", "GzScene3D"), ("name", "3D View")], None, vec![
                    e("ignition-gui", &[], None, vec![
                        e("title", &[], Some("3D View"), vec![]),
                        e("property", &[("type", "bool"), ("key", "showTitleBar")], Some("false"), vec![]),
                        e("property", &[("type", "string"), ("key", "state")], Some("docked"), vec![]),
                    ]),
                    e("engine", &[], Some("ogre2"), vec![]),
                    e("scene", &[], Some("scene"), vec![]),
                    e("ambient_light", &[], Some("0.4 0.4 0.4"), vec![]),
                    e("background_color", &[], Some("0.8 0.8 0.8"), vec![]),
                    e("camera_pose", &[], Some("-6 0 6 0 0.5 0"), vec![]),
                ]),
                e("plugin", &[("filename", "WorldControl"), ("name", "World control")], None, vec![
                    e("ignition-gui", &[], None, vec![
                        e("title", &[], Some("World control"), vec![]),
                        e("property", &[("type", "bool"), ("key", "showTitleBar")], Some("false"), vec![]),
                        e("property", &[("type", "bool"), ("key", "resizable")], Some("false"), vec![]),
                        e("property", &[("type", "double"), ("key", "height")], Some("72"), vec![]),
                        e("property", &[("type", "double"), ("key", "width")], Some("121"), vec![]),
                        e("property", &[("type", "double"), ("key", "z")], Some("1"), vec![]),
                        e("property", &[("type", "string"), ("key", "state")], Some("floating"), vec![]),
                        e("anchors", &[("target", "3D View")], None, vec![
                            e("line", &[("own", "left"), ("target", "left")], None, vec![]),
                            e("line", &[("own", "bottom"), ("target", "bottom")], None, vec![]),
                        ]),
                    ]),
                    e("play_pause", &[], Some("true"), vec![]),
                    e("step", &[], Some("true"), vec![]),
                    e("start_paused", &[], Some("true"), vec![]),
                ]),
                e("plugin", &[("filename", "WorldStats"), ("name", "World stats")], None, vec![
                    e("ignition-gui", &[], None, vec![
                        e("title", &[], Some("World stats"), vec![]),
                        e("property", &[("type", "bool"), ("key", "showTitleBar")], Some("false"), vec![]),
                        e("property", &[("type", "bool"), ("key", "resizable")], Some("false"), vec![]),
                        e("property", &[("type", "double"), ("key", "height")], Some("110"), vec![]),
                        e("property", &[("type", "double"), ("key", "width")], Some("290"), vec![]),
                        e("property", &[("type", "double"), ("key", "z")], Some("1"), vec![]),
                        e("property", &[("type", "string"), ("key", "state")], Some("floating"), vec![]),
                        e("anchors", &[("target", "3D View")], None, vec![
                            e("line", &[("own", "right"), ("target", "right")], None, vec![]),
                            e("line", &[("own", "bottom"), ("target", "bottom")], None, vec![]),
                        ]),
                    ]),
                    e("sim_time", &[], Some("true"), vec![]),
                    e("real_time", &[], Some("true"), vec![]),
                    e("real_time_factor", &[], Some("true"), vec![]),
                    e("iterations", &[], Some("true"), vec![]),
                ]),
                e("plugin", &[("filename", "TransformControl"), ("name", "Transform control")], None, vec![
                    e("ignition-gui", &[], None, vec![
                        e("title", &[], Some("Transform control"), vec![]),
                        e("anchors", &[("target", "3D View")], None, vec![
                            e("line", &[("own", "left"), ("target", "left")], None, vec![]),
                            e("line", &[("own", "top"), ("target", "top")], None, vec![]),
                        ]),
                        e("property", &[("key", "resizable"), ("type", "bool")], Some("false"), vec![]),
                        e("property", &[("key", "width"), ("type", "double")], Some("230"), vec![]),
                        e("property", &[("key", "height"), ("type", "double")], Some("50"), vec![]),
                        e("property", &[("key", "state"), ("type", "string")], Some("floating"), vec![]),
                        e("property", &[("key", "showTitleBar"), ("type", "bool")], Some("false"), vec![]),
                        e("property", &[("key", "cardBackground"), ("type", "string")], Some("#666666"), vec![]),
                    ]),
                ]),
                e("plugin", &[("filename", "Shapes"), ("name", "Shapes")], None, vec![
                    e("ignition-gui", &[], None, vec![
                        e("anchors", &[("target", "Transform control")], None, vec![
                            e("line", &[("own", "left"), ("target", "right")], None, vec![]),
                            e("line", &[("own", "top"), ("target", "top")], None, vec![]),
                        ]),
                        e("property", &[("key", "resizable"), ("type", "bool")], Some("false"), vec![]),
                        e("property", &[("key", "width"), ("type", "double")], Some("200"), vec![]),
                        e("property", &[("key", "height"), ("type", "double")], Some("50"), vec![]),
                        e("property", &[("key", "state"), ("type", "string")], Some("floating"), vec![]),
                        e("property", &[("key", "showTitleBar"), ("type", "bool")], Some("false"), vec![]),
                        e("property", &[("key", "cardBackground"), ("type", "string")], Some("#666666"), vec![]),
                    ]),
                ]),
                e("plugin", &[("filename", "ComponentInspector"), ("name", "Component inspector")], None, vec![
                    e("ignition-gui", &[], None, vec![
                        e("property", &[("type", "bool"), ("key", "showTitleBar")], Some("false"), vec![]),
                        e("property", &[("type", "string"), ("key", "state")], Some("docked"), vec![]),
                    ]),
                ]),
                e("plugin", &[("filename", "EntityTree"), ("name", "Entity tree")], None, vec![
                    e("ignition-gui", &[], None, vec![
                        e("property", &[("type", "bool"), ("key", "showTitleBar")], Some("false"), vec![]),
                        e("property", &[("type", "string"), ("key", "state")], Some("docked"), vec![]),
                    ]),
                ]),
                e("plugin", &[("filename", "toggle_charging"), ("name", "toggle_charging")], None, vec![]),
            ]),
            e("light", &[("type", "directional"), ("name", "sun")], None, vec![
                e("cast_shadows", &[], Some("true"), vec![]),
                e("pose", &[], Some("0 0 10 0 0 0"), vec![]),
                e("diffuse", &[], Some("1 1 1 1"), vec![]),
                e("specular", &[], Some("0.2 0.2 0.2 1"), vec![]),
                e("attenuation", &[], None, vec![
                    e("range", &[], Some("1000"), vec![]),
                    e("constant", &[], Some("0.09"), vec![]),
                    e("linear", &[], Some("0.001"), vec![]),
                    e("quadratic", &[], Some("0.001"), vec![]),
                ]),
                e("direction", &[], Some("-0.5 0.1 -0.9"), vec![]),
            ]),
        ]),
    ])
}

pub(super) fn classic() -> Element {
    e("sdf", &[("version", "1.7")], None, vec![
        e("world", &[("name", "sim_world")], None, vec![
            e("scene", &[], None, vec![
                e("ambient", &[], Some("0.8 0.8 0.8 1.0"), vec![]),
                e("background", &[], Some("0 0 0"), vec![]),
                e("grid", &[], Some("false"), vec![]),
            ]),
            e("include", &[], None, vec![
                e("uri", &[], Some("model://sun"), vec![]),
            ]),
            e("gui", &[], None, vec![
                e("camera", &[("name", "gui_camera")], None, vec![
                    e("pose", &[], Some("10 -20 10 0 0.6 1.57"), vec![]),
                ]),
            ]),
        ]),
    ])
}
