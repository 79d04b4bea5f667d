//! The room of the paper's experiments (§V): walls, and the five PPS-tagged devices, the
//! switches on a wall at about 1.2 m, the lamp, drawer and trash can each next to a wall, plus
//! reddish-brown wooden furniture to tempt the red segmentation. [`RoomOptions::home`] adds what
//! homes have and the paper's lab did not: red things that are not tags beside the tagged
//! devices, the two switches' tags 30 cm apart, lacquered fronts that mirror the flash, a
//! plywood drawer cabinet whose grain passes the factory's red, and evening light.

use nalgebra::{Point3, Vector3};
use pps_schema::Epc;

use super::scene::{LightSource, Scene, Surface, WallFrame};

/// The five devices of the paper.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum DeviceKind {
    LightSwitch,
    AdaLightSwitch,
    Lamp,
    Drawer,
    TrashCan,
}

impl DeviceKind {
    pub const ALL: [Self; 5] =
        [Self::LightSwitch, Self::AdaLightSwitch, Self::Lamp, Self::Drawer, Self::TrashCan];

    /// The entry's `type`, as the paper and the seed tags name it.
    pub fn type_name(self) -> &'static str {
        match self {
            Self::LightSwitch => "light switch",
            Self::AdaLightSwitch => "ada light switch",
            Self::Lamp => "lamp",
            Self::Drawer => "drawer",
            Self::TrashCan => "trash can",
        }
    }

    /// The EPC of the device's tag (the seed tags' keys).
    pub fn epc(self) -> Epc {
        let hex = match self {
            Self::LightSwitch => "355AB1C60000001000000001",
            Self::AdaLightSwitch => "355AB1C60000002000000001",
            Self::Lamp => "355AB1C60000003000000001",
            Self::Drawer => "355AB1C60000004000000001",
            Self::TrashCan => "355AB1C60000005000000001",
        };
        Epc::parse(hex).expect("the seed EPCs are valid")
    }

    /// Accepts the type name with spaces, hyphens or underscores (`trash-can`, `ada light switch`).
    pub fn parse(name: &str) -> Option<Self> {
        let wanted = name.trim().to_ascii_lowercase().replace(['-', '_'], " ");
        Self::ALL.into_iter().find(|k| k.type_name() == wanted)
    }
}

/// A tagged device: where its tag is and which way the tag faces, world frame.
#[derive(Debug, Clone, PartialEq)]
pub struct Device {
    pub kind: DeviceKind,
    pub epc: Epc,
    /// Centre of the red tag material, metres.
    pub tag_center: Point3<f64>,
    /// Unit horizontal direction the tag faces, into the room.
    pub tag_normal: Vector3<f64>,
}

/// Variations of the room for tests.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RoomOptions {
    /// Red tags as in the paper; false paints them blue, leaving nothing red but wood grain.
    pub red_tags: bool,
    /// Distance along the wall between the flip switch and the rocker switch, metres.
    pub switch_spacing: f32,
    /// How much higher than the paper's (1.2 m and 1.22 m) both switches sit, metres.
    pub switch_raise: f32,
    /// Where the floor lamp and the trash can stand along their walls, metres from the walls'
    /// left ends as seen from the room.
    pub lamp_along: f32,
    pub trash_can_along: f32,
    pub wood_furniture: bool,
    /// Red things that are not tags within 30 cm of the tags (a book on the cabinet, a scarf on
    /// the lamp's pole, a cloth over the trash can's side, a picture by the switch), and
    /// lacquered drawer fronts and trash can that mirror the flash.
    pub clutter: bool,
    /// Evening: little daylight, the rooms lit mainly by their lamps.
    pub evening: bool,
    /// The drawer cabinet is orange-brown plywood whose grain the factory's red thresholds take
    /// for red (issue 34), its fronts too unless they are lacquered.
    pub plywood_cabinet: bool,
    /// The drawer's towel is orange-red rather than the paper's red: a household's tags need not
    /// all be one red, and the colour learned from all of them then reaches into orange.
    pub orange_towel: bool,
    /// The rocker switch sits in the upper gang of a plywood double plate, the lower gang blank:
    /// wood touches the rocker's patch and stretches 15 cm below it.
    pub wooden_rocker_plate: bool,
    /// A red plastic key box on the wall right of the rocker switch, touching its plate: as red
    /// as the tag, 8 × 10 cm and standing 4 cm out from the wall.
    pub red_box_by_rocker: bool,
    /// A footstool in the room straight out from the rocker switch, 1.1–1.5 m from its wall:
    /// 40 cm square and 45 cm high, off the way of a robot that comes to the switch from the
    /// side, and behind it once it faces the switch.
    pub footstool_by_rocker: bool,
}

impl RoomOptions {
    /// A home rather than a lab: clutter, the two switches' tags 30 cm apart, evening light.
    pub fn home() -> Self {
        Self {
            clutter: true,
            evening: true,
            switch_spacing: 0.3,
            plywood_cabinet: true,
            ..Self::default()
        }
    }

    /// The room a command line names: `paper` (the lab of the paper's trials) or `home`.
    pub fn named(name: &str) -> Result<Self, String> {
        match name {
            "paper" => Ok(Self::default()),
            "home" => Ok(Self::home()),
            _ => Err(format!(
                "`{name}` is not a room: paper (the paper's lab) or home (clutter, evening light)"
            )),
        }
    }
}

impl Default for RoomOptions {
    fn default() -> Self {
        Self {
            red_tags: true,
            switch_spacing: 2.5,
            switch_raise: 0.0,
            lamp_along: 4.5,
            trash_can_along: 2.65,
            wood_furniture: true,
            clutter: false,
            evening: false,
            plywood_cabinet: false,
            orange_towel: false,
            wooden_rocker_plate: false,
            red_box_by_rocker: false,
            footstool_by_rocker: false,
        }
    }
}

/// The room: its geometry, its devices and where its lights are.
#[derive(Debug, Clone)]
pub struct Room {
    pub scene: Scene,
    pub devices: Vec<Device>,
    pub ceiling_light: Point3<f32>,
    pub lamp_light: Point3<f32>,
    /// Irradiance from daylight through the windows, on every surface alike.
    pub daylight: f32,
}

const WIDTH: f32 = 7.0; // along x
const DEPTH: f32 = 6.0; // along y
const HEIGHT: f32 = 2.5;

const WALL: Surface = Surface::Matte([0.70, 0.67, 0.60]);
const FLOOR: Surface = Surface::Matte([0.30, 0.28, 0.25]);
const PLASTIC: Surface = Surface::Matte([0.74, 0.73, 0.69]);
const LAMINATE: Surface = Surface::Matte([0.60, 0.60, 0.57]);
const PLYWOOD: Surface = Surface::Plywood;
const METAL: Surface = Surface::Matte([0.35, 0.35, 0.37]);
const DARK_PLASTIC: Surface = Surface::Matte([0.12, 0.12, 0.13]);
const BLUE: Surface = Surface::Matte([0.05, 0.09, 0.35]);
const FOAM: Surface = Surface::Matte([0.55, 0.030, 0.035]);
const DYCEM: Surface = Surface::Matte([0.50, 0.025, 0.040]);
const TOWEL: Surface = Surface::Matte([0.45, 0.020, 0.030]);
/// An orange-red towel: hue 15°, saturation 0.9, value 0.7 in sRGB.
const ORANGE_TOWEL: Surface = Surface::Matte([0.448, 0.042, 0.006]);
/// Red things that are not tags: as red as the tags, so colour alone cannot tell them apart.
const RED_BOOK: Surface = Surface::Matte([0.48, 0.022, 0.030]);
const RED_CLOTH: Surface = Surface::Matte([0.52, 0.028, 0.034]);
/// A footstool's blue-grey upholstery.
const FABRIC: Surface = Surface::Matte([0.18, 0.21, 0.28]);

impl Room {
    /// The paper's room with the default options.
    pub fn paper() -> Self {
        Self::new(RoomOptions::default())
    }

    pub fn new(options: RoomOptions) -> Self {
        let red = |s: Surface| if options.red_tags { s } else { BLUE };
        let north = WallFrame { origin: Point3::new(0.0, DEPTH, 0.0), out: -Vector3::y() };
        let east = WallFrame { origin: Point3::new(WIDTH, DEPTH, 0.0), out: -Vector3::x() };
        let south = WallFrame { origin: Point3::new(WIDTH, 0.0, 0.0), out: Vector3::y() };
        let west = WallFrame { origin: Point3::origin(), out: Vector3::x() };
        let mut parts = vec![
            north.cuboid(
                "north wall",
                [WIDTH / 2.0, -0.05, HEIGHT / 2.0],
                [WIDTH / 2.0 + 0.1, 0.05, HEIGHT / 2.0],
                WALL,
            ),
            south.cuboid(
                "south wall",
                [WIDTH / 2.0, -0.05, HEIGHT / 2.0],
                [WIDTH / 2.0 + 0.1, 0.05, HEIGHT / 2.0],
                WALL,
            ),
            east.cuboid(
                "east wall",
                [DEPTH / 2.0, -0.05, HEIGHT / 2.0],
                [DEPTH / 2.0 + 0.1, 0.05, HEIGHT / 2.0],
                WALL,
            ),
            west.cuboid(
                "west wall",
                [DEPTH / 2.0, -0.05, HEIGHT / 2.0],
                [DEPTH / 2.0 + 0.1, 0.05, HEIGHT / 2.0],
                WALL,
            ),
            north.cuboid(
                "floor",
                [WIDTH / 2.0, DEPTH / 2.0, -0.05],
                [WIDTH / 2.0, DEPTH / 2.0, 0.05],
                FLOOR,
            ),
            north.cuboid(
                "ceiling",
                [WIDTH / 2.0, DEPTH / 2.0, HEIGHT + 0.05],
                [WIDTH / 2.0, DEPTH / 2.0, 0.05],
                Surface::Matte([0.75; 3]),
            ),
        ];
        let ceiling_light = Point3::new(WIDTH / 2.0, DEPTH / 2.0, HEIGHT - 0.1);
        parts.push(north.cylinder(
            "ceiling fixture",
            [WIDTH / 2.0, DEPTH / 2.0, HEIGHT - 0.02],
            [0.0, 0.0, 1.0],
            0.02,
            0.25,
            Surface::Glowing { reflectance: [0.8; 3], source: LightSource::Ceiling, radiance: 4.0 },
        ));
        let mut devices = Vec::new();
        let mut tag = |kind: DeviceKind, wall: &WallFrame, at: [f32; 3]| {
            devices.push(Device {
                kind,
                epc: kind.epc(),
                tag_center: wall.point(at[0], at[1], at[2]).cast(),
                tag_normal: wall.out.cast(),
            });
        };

        // Flip-type light switch, its toggle in a red foam tube pointing out and 20° up.
        let (a, (s, c)) = (2.0, 20f32.to_radians().sin_cos());
        let h = 1.2 + options.switch_raise;
        parts.push(north.cuboid("switch plate", [a, 0.003, h], [0.035, 0.003, 0.0575], PLASTIC));
        let foam = [a, 0.008 + 0.015 * c, h + 0.015 * s];
        parts.push(north.cylinder("switch foam tube", foam, [0.0, c, s], 0.015, 0.013, red(FOAM)));
        tag(DeviceKind::LightSwitch, &north, foam);

        // ADA rocker switch, its paddle under a red Dycem patch.
        let (a, h) = (2.0 + options.switch_spacing, 1.22 + options.switch_raise);
        if options.wooden_rocker_plate {
            // A double plate 7 × 23.5 cm, its top where the single plate's is.
            let (half, plate) = (0.1175, PLYWOOD);
            parts.push(north.cuboid(
                "rocker plate",
                [a, 0.003, h + 0.0575 - half],
                [0.035, 0.003, half],
                plate,
            ));
        } else {
            parts.push(north.cuboid(
                "rocker plate",
                [a, 0.003, h],
                [0.035, 0.003, 0.0575],
                PLASTIC,
            ));
        }
        parts.push(north.cuboid("rocker paddle", [a, 0.009, h], [0.018, 0.003, 0.033], PLASTIC));
        parts.push(north.cuboid("rocker dycem", [a, 0.0135, h], [0.03, 0.0015, 0.03], red(DYCEM)));
        if options.red_box_by_rocker {
            parts.push(north.cuboid(
                "red key box",
                [a + 0.075, 0.02, h],
                [0.04, 0.02, 0.05],
                RED_BOOK,
            ));
        }
        tag(DeviceKind::AdaLightSwitch, &north, [a, 0.0135, h]);
        if options.footstool_by_rocker {
            parts.push(north.cuboid("footstool", [a, 1.3, 0.225], [0.2, 0.2, 0.225], FABRIC));
        }

        // Floor lamp by the south wall, its pull chain toward the room, red foam on the chain.
        let a = options.lamp_along;
        let lamp_light = south.point(a, 0.25, 1.42);
        parts.push(south.cylinder(
            "lamp base",
            [a, 0.25, 0.015],
            [0.0, 0.0, 1.0],
            0.015,
            0.14,
            METAL,
        ));
        parts.push(south.cylinder(
            "lamp pole",
            [a, 0.25, 0.75],
            [0.0, 0.0, 1.0],
            0.72,
            0.012,
            METAL,
        ));
        parts.push(south.cylinder(
            "lamp shade",
            [a, 0.25, 1.42],
            [0.0, 0.0, 1.0],
            0.13,
            0.17,
            Surface::Glowing {
                reflectance: [0.80, 0.75, 0.60],
                source: LightSource::Lamp,
                radiance: 2.0,
            },
        ));
        parts.push(south.cylinder(
            "lamp chain",
            [a, 0.40, 1.20],
            [0.0, 0.0, 1.0],
            0.09,
            0.002,
            METAL,
        ));
        parts.push(south.cylinder(
            "lamp chain foam",
            [a, 0.40, 1.08],
            [0.0, 0.0, 1.0],
            0.03,
            0.012,
            red(FOAM),
        ));
        tag(DeviceKind::Lamp, &south, [a, 0.40, 1.08]);

        // Drawer cabinet against the east wall; a red towel hangs from the top drawer's handle.
        let a = 3.775;
        let lacquer = |s: Surface| match s {
            Surface::Matte(reflectance) if options.clutter => {
                Surface::Glossy { reflectance, shine: 4.0 }
            }
            other => other,
        };
        let body = if options.plywood_cabinet { PLYWOOD } else { LAMINATE };
        parts.push(east.cuboid("cabinet", [a, 0.225, 0.375], [0.225, 0.225, 0.375], body));
        let front =
            if options.plywood_cabinet && !options.clutter { PLYWOOD } else { lacquer(PLASTIC) };
        parts.push(east.cuboid("top drawer", [a, 0.4575, 0.56], [0.205, 0.0075, 0.16], front));
        parts.push(east.cuboid("bottom drawer", [a, 0.4575, 0.20], [0.205, 0.0075, 0.17], front));
        parts.push(east.cuboid("drawer handle", [a, 0.477, 0.64], [0.06, 0.012, 0.01], METAL));
        let towel = if options.orange_towel { ORANGE_TOWEL } else { TOWEL };
        parts.push(east.cuboid("drawer towel", [a, 0.495, 0.52], [0.08, 0.004, 0.12], red(towel)));
        tag(DeviceKind::Drawer, &east, [a, 0.495, 0.52]);

        // Trash can against the west wall, a red Dycem patch near the top of its front.
        let a = options.trash_can_along;
        let can = lacquer(DARK_PLASTIC);
        parts.push(west.cuboid("trash can", [a, 0.145, 0.225], [0.15, 0.125, 0.225], can));
        parts.push(west.cuboid(
            "trash can dycem",
            [a, 0.2715, 0.36],
            [0.05, 0.0015, 0.04],
            red(DYCEM),
        ));
        tag(DeviceKind::TrashCan, &west, [a, 0.2715, 0.36]);

        if options.clutter {
            let (switch, lamp, can, cabinet) =
                (2.0, options.lamp_along, options.trash_can_along, 3.775);
            // A red picture on the wall 30 cm to the flip switch's left, at its height.
            let h = 1.25 + options.switch_raise;
            parts.push(north.cuboid(
                "red picture",
                [switch - 0.3, 0.01, h],
                [0.08, 0.01, 0.1],
                RED_BOOK,
            ));
            // A red scarf wound round the lamp's pole 25 cm below its tag.
            parts.push(south.cylinder(
                "red scarf",
                [lamp, 0.25, 0.86],
                [0.0, 0.0, 1.0],
                0.06,
                0.03,
                RED_CLOTH,
            ));
            // A red cloth hung over the trash can's right side, 22 cm from its tag.
            parts.push(west.cuboid(
                "red cloth",
                [can + 0.153, 0.17, 0.36],
                [0.003, 0.08, 0.07],
                RED_CLOTH,
            ));
            // A red book lying on the cabinet, toward its front, 30 cm from the towel.
            parts.push(east.cuboid(
                "red book",
                [cabinet + 0.12, 0.37, 0.77],
                [0.11, 0.07, 0.02],
                RED_BOOK,
            ));
        }
        if options.wood_furniture {
            parts.push(north.cuboid("sideboard", [3.5, 0.2, 0.4], [0.4, 0.2, 0.4], Surface::Wood));
            parts.push(east.cuboid(
                "bookshelf",
                [2.65, 0.17, 0.6],
                [0.4, 0.17, 0.6],
                Surface::Wood,
            ));
            parts.push(south.cuboid(
                "side table",
                [3.8, 0.25, 0.275],
                [0.2, 0.2, 0.275],
                Surface::Wood,
            ));
            parts.push(west.cuboid("chest", [1.6, 0.25, 0.3], [0.35, 0.25, 0.3], Surface::Wood));
        }
        let daylight = if options.evening { 0.012 } else { 0.05 };
        Self { scene: Scene::new(parts), devices, ceiling_light, lamp_light, daylight }
    }

    pub fn device(&self, kind: DeviceKind) -> &Device {
        self.devices.iter().find(|d| d.kind == kind).expect("the room has every device")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_tag_is_visible_from_half_a_metre_out() {
        let room = Room::paper();
        for device in &room.devices {
            let eye: Point3<f32> = (device.tag_center + device.tag_normal * 0.5).cast();
            let dir: Vector3<f32> = (-device.tag_normal).cast();
            let hit = room.scene.cast(&eye, &dir, 2.0).unwrap();
            let name = room.scene.parts()[hit.part].name;
            assert!(
                name.contains("foam") || name.contains("dycem") || name.contains("towel"),
                "{:?} sees {name}",
                device.kind
            );
        }
        assert_eq!(DeviceKind::parse("trash-can"), Some(DeviceKind::TrashCan));
        assert_eq!(DeviceKind::parse("ADA_light_switch"), Some(DeviceKind::AdaLightSwitch));
        assert_eq!(DeviceKind::parse("toaster"), None);
    }
}
