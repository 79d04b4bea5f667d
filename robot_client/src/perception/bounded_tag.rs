//! A tag is a bounded thing (issue 34). A red region larger than any tag in the home (a
//! plywood cabinet whose orange-brown passes the thresholds, a red bin touching the towel), by
//! its reach or, where the tags' sizes are known, by its width ([`super::tag_bound`]), is
//! never the tag as a whole. Where its part nearest the target has a hue no tag has (a wood's
//! under warm light), only its points of a tag's red are searched ([`super::unmistakable_red`]).
//! Then it is divided, by colour first, then by surface, and last by the two colours, then the
//! two surfaces a few millimetres apart, its voxels may fall into ([`super::two_clusters`]),
//! and where the home's tags' sizes are known, by the shape of a tag standing out of it
//! ([`super::tag_shape`]). When its part nearest the target stays larger than a tag, that part
//! is not the tag the person pointed at, and only a tag-sized part of the region beside it,
//! about as near the target, may be ([`super::tag::choose_tag`]). Every division and every
//! refusal is said in words.
//!
//! A region no larger than a tag is divided by two colours alone: two colours whose voxels lie
//! clearly apart are two things whatever their size (a small patch and the red plastic against
//! it make a region no larger than a towel), and a tag of one colour is left as it was.
//!
//! Every division takes its limits from the data: the tag's colour is the colour of the part
//! nearest the pointed location, within that part's own spread, the tag's surface is the one
//! that part lies on, within the noise measured on it, two colours or two surfaces are two
//! when their voxels' clusters lie four of their own spreads apart, and a tag's shape is as
//! wide as the home's widest tag registered.

use nalgebra::{Matrix3, Point3, Vector3};
use rustc_hash::FxHashSet;

use super::core_colour::{ColourOf, tag_coloured};
use super::edge_strips::{dense_in_the_picture, off_the_strips};
use super::mask::Mask;
use super::occupancy::{Component, OccupancyGrid};
use super::tag::about_as_near;
use super::tag_against_a_side::against_a_side;
use super::tag_bound::{TagBound, TooLarge};
use super::tag_search_params::TagSearchParams;
use super::tag_shape::out_of_reach_of_a_disc;
use super::tag_sighting::TagDetection;
use super::two_clusters::of_the_core_cluster;
use super::two_colours::{
    colours_around, colours_at, colours_of, mean_colour_around, pixel_finder, pixels_of,
};
use super::unmistakable_red::{UNMISTAKABLE_HUES, unmistakably_red};
use crate::hal::{CameraCalibration, ColorImage};

/// Half the width of a surface's band, in standard deviations of the tag's own points about
/// it: three hold all but 0.3 % of a surface's noise.
const SURFACE_BAND_SIGMAS: f64 = 3.0;

/// How many pixels around a point's own the colour split averages over. A towel's pixels
/// scatter 0.05–0.10 on the chroma disc in the camera's noise (hue ±10°, saturation ±0.1),
/// as far as a third of the way to an orange-brown wood's; the mean of the nine pixels one
/// around scatters a third as far, and mixes only the ring of pixels at an edge.
const PIXEL_NOISE_REACH: u32 = 1;

/// How far outside the search's colours, in the voxels' pooled spread, a second colour may
/// lie and still be a red the search takes: at two, 2 % of its voxels or more pass the
/// thresholds, as a red fabric's do whose middle lies a hair under the least saturation
/// (0.56–0.60 under 0.6 in warm light), while a tag's pale folds and shadows lie ten spreads
/// and more away (a towel's fold: saturation 0.38).
const RED_REACH_SPREADS: f32 = 2.0;

/// The components with each one near the target that is larger than any tag (`bound`), or of
/// two colours, divided into the parts a tag could be; `notes` says what was divided and why.
/// `join` joins the fragments of one tag that its voxels alone leave apart (a towel at a steep
/// angle, sampled sparsely), as the search joined them before the division: a division must
/// not break the tag it frees.
#[allow(clippy::too_many_arguments)]
pub(super) fn bound_tags(
    components: Vec<Component>,
    image: &ColorImage,
    calibration: &CameraCalibration,
    target: &Point3<f64>,
    params: &TagSearchParams,
    bound: &TagBound,
    join: &dyn Fn(Vec<Component>) -> Vec<Component>,
    notes: &mut Vec<String>,
) -> Vec<Component> {
    let mut bounded = Vec::with_capacity(components.len());
    let components: Vec<Component> = components
        .into_iter()
        .flat_map(|component| {
            match of_unmistakable_red(&component, image, calibration, target, params, bound, notes)
            {
                Some(parts) => join(parts),
                None => vec![component],
            }
        })
        .collect();
    for component in components {
        if component.distance_to_target > params.max_distance {
            bounded.push(component);
            continue;
        }
        let Some(too_large) = bound.too_large(&component) else {
            bounded.extend(tag_sized(component, image, calibration, target, params, join, notes));
            continue;
        };
        // Reaching no further than a tag but wider or longer, it is first divided by two
        // colours, voxel by voxel, as a region of a tag's size is: that parts a tube from the
        // fabric hanging beside it where the colour of the part nearest the target (below)
        // keeps the fabric and loses the tube.
        if let TooLarge::Wide { .. } | TooLarge::Long { .. } = too_large {
            let mut said = Vec::new();
            let any = OtherColour::Any;
            if let Some(parts) =
                of_two_colours(&component, image, calibration, target, params, any, &mut said)
            {
                let parts = join(parts);
                if nearest_part(&parts, params).is_some_and(|part| bound.holds(part)) {
                    notes.extend(said);
                    bounded.extend(parts);
                    continue;
                }
            }
        }
        let region = component.members.clone();
        let mut members = component.members;
        let colours = colours_around(&members, image, calibration, PIXEL_NOISE_REACH);
        match tag_coloured(
            &members,
            &colours,
            &core_of(&members, target, params),
            params.voxel_size,
        ) {
            Some(split) => {
                notes.push(format!(
                    "the red region near the target is {too_large}: {} of its {} points have \
                     the colour of its part nearest the target (within three of that part's \
                     spreads, {:.3} on the chroma disc), the rest another",
                    split.kept.len(),
                    members.len(),
                    split.spread,
                ));
                members = split.kept;
            }
            None => notes.push(format!(
                "the red region near the target is {too_large}, and all of it has the colour of \
                 its part nearest the target"
            )),
        }
        let mut divided = Vec::new();
        for part in join(components_of(&members, target, params)) {
            if part.distance_to_target > params.max_distance || bound.holds(&part) {
                divided.push(part);
                continue;
            }
            match on_the_nearest_surface(&part, target, params) {
                Some(surface) => {
                    notes.push(format!(
                        "a part {:.0} cm across was cut to the surface its part nearest the \
                         target lies on (within {:.1} mm, three times the noise measured \
                         there): {} of its {} points",
                        part.radius * 200.0,
                        surface.band * 1e3,
                        surface.kept.len(),
                        part.points,
                    ));
                    divided.extend(join(components_of(&surface.kept, target, params)));
                }
                None => divided.push(part),
            }
        }
        // The tag the person pointed at is the part nearest the target. When that part is
        // still larger than any tag, the region's other parts are pieces of the same red thing
        // or of what touches it, and taking one of them would put the tag where it is not.
        // Each step below divides it further; its size is judged again only when one did.
        let mut stuck = nearest_too_large(&divided, params, bound);
        if let Some((i, _)) = stuck
            && let Some(parts) = of_two_colours(
                &divided[i],
                image,
                calibration,
                target,
                params,
                OtherColour::Any,
                notes,
            )
        {
            divided = join(parts);
            stuck = nearest_too_large(&divided, params, bound);
        }
        if let Some((i, _)) = stuck
            && let Some(parts) = of_two_surfaces(&divided[i], target, params, notes)
        {
            divided = join(parts);
            stuck = nearest_too_large(&divided, params, bound);
        }
        if let Some((i, _)) = stuck
            && let Some(parts) = standing_out(&divided[i], &region, target, params, notes)
        {
            divided = join(parts);
            stuck = nearest_too_large(&divided, params, bound);
        }
        let beside_of = |part: &Component| {
            tag_sized_beside(&region, part, image, calibration, target, params, bound, join)
        };
        // The tag-sized parts beside the part stuck nearest the target, found once for it and
        // again only after a step has divided it.
        let mut beside = None;
        // A tag against the red thing by a whole side is looked for only where no part of the
        // region beside it is tag-sized and about as near the target: one is a tag of a colour
        // of its own, and past the rectangle's side against it the red thing's colour would
        // end as at a free side.
        if let Some((i, _)) = stuck {
            let found = beside_of(&divided[i]);
            let a_tag_beside = found.iter().any(|part| about_as_near(part, &divided[i], params));
            beside = Some(found);
            if !a_tag_beside
                && let Some(parts) = lying_against_it(
                    &divided[i],
                    &region,
                    image,
                    calibration,
                    target,
                    params,
                    notes,
                )
            {
                divided = join(parts);
                stuck = nearest_too_large(&divided, params, bound);
                beside = None;
            }
        }
        // What the shape leaves may reach no further than a tag and still be wider: a tube
        // and the strip of the fabric beside it that the disc could not take. Alone, their two
        // colours lie apart as the fabric's many points kept them from doing in the whole part.
        if let Some((i, TooLarge::Wide { .. })) = stuck
            && let Some(parts) = of_two_colours(
                &divided[i],
                image,
                calibration,
                target,
                params,
                OtherColour::Any,
                notes,
            )
        {
            divided = join(parts);
            stuck = nearest_too_large(&divided, params, bound);
            beside = None;
        }
        match stuck {
            // Kept whole, so that `choose_tag` knows the red thing nearest the target is not a
            // tag and `too_large_nearest` can say why; beside it, the rest of the region's
            // tag-sized parts, one of which may be the tag the person pointed at.
            Some((i, _)) => {
                let part = &divided[i];
                let beside = beside.unwrap_or_else(|| beside_of(part));
                bounded.push(part.clone());
                bounded.extend(beside);
            }
            // The parts a division left near the target and no larger than a tag may still be
            // two things, as a region of a tag's size may.
            None => {
                for part in divided {
                    if part.distance_to_target <= params.max_distance && bound.holds(&part) {
                        let parts =
                            tag_sized(part, image, calibration, target, params, join, notes);
                        bounded.extend(parts);
                    } else {
                        bounded.push(part);
                    }
                }
            }
        }
    }
    bounded
}

/// The parts of the unmistakable red ([`unmistakably_red`]) of `component`, when it lies near
/// the target, is larger than any tag, and its part nearest the target has a hue only a home
/// material has: a wood's, a brick's, a leather's, a skin's. `None` when not, or when that red
/// holds no part near the target: the region is then divided as any other.
#[allow(clippy::too_many_arguments)]
fn of_unmistakable_red(
    component: &Component,
    image: &ColorImage,
    calibration: &CameraCalibration,
    target: &Point3<f64>,
    params: &TagSearchParams,
    bound: &TagBound,
    notes: &mut Vec<String>,
) -> Option<Vec<Component>> {
    if component.distance_to_target > params.max_distance {
        return None;
    }
    let too_large = bound.too_large(component)?;
    let members = &component.members;
    let red = unmistakably_red(
        members,
        &core_of(members, target, params),
        image,
        calibration,
        &params.thresholds,
        params.voxel_size,
        PIXEL_NOISE_REACH,
    )?;
    let parts = components_of(&red.kept, target, params);
    let near = |part: &Component| {
        part.distance_to_target <= params.max_distance && part.points >= params.min_points
    };
    if !parts.iter().any(near) {
        return None;
    }
    let [from, to] = UNMISTAKABLE_HUES;
    notes.push(format!(
        "the red region near the target is {too_large}, and its part nearest the target has hue \
         {:.0}°, outside a tag's red ({from:.0}–{to:.0}°), where wood, brick, leather and skin \
         lie: {} of its {} points have a tag's red, and only they are searched",
        red.nearest_hue,
        red.kept.len(),
        component.points,
    ));
    Some(parts)
}

/// `part`, no larger than a tag, divided into its two things when it is two: a rocker's small
/// patch and the red plastic against it make a region no larger than a towel, and a lamp's
/// pull chain seen before a wooden wall joins the tube.
fn tag_sized(
    part: Component,
    image: &ColorImage,
    calibration: &CameraCalibration,
    target: &Point3<f64>,
    params: &TagSearchParams,
    join: &dyn Fn(Vec<Component>) -> Vec<Component>,
    notes: &mut Vec<String>,
) -> Vec<Component> {
    let red = OtherColour::Red;
    match of_two_colours(&part, image, calibration, target, params, red, notes) {
        Some(parts) => join(parts),
        None => vec![part],
    }
}

/// The parts of `region` no larger than a tag once `part`, a red thing too large to be one,
/// is taken out of it: one of them may be the tag the person pointed at beside it.
///
/// A person's pointing is centimetres off, so a red thing lying against the tag is often
/// nearer the pointed location than the tag is, and the division, anchored there, cut the red
/// thing out and left the tag aside. Taken with it are the rest's points of its colour (its
/// edges, its faces on other surfaces), which would otherwise join into a fringe around the
/// tag; a tag of the red thing's own colour goes with them, so nothing is made of the fringe.
/// What is left is divided as the region was, by the colour of its part nearest the target.
#[allow(clippy::too_many_arguments)]
fn tag_sized_beside(
    region: &[Point3<f32>],
    part: &Component,
    image: &ColorImage,
    calibration: &CameraCalibration,
    target: &Point3<f64>,
    params: &TagSearchParams,
    bound: &TagBound,
    join: &dyn Fn(Vec<Component>) -> Vec<Component>,
) -> Vec<Component> {
    let bits = |p: &Point3<f32>| [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()];
    let taken: FxHashSet<[u32; 3]> = part.members.iter().map(bits).collect();
    let pixels = pixels_of(region, image, calibration);
    let dense = dense_in_the_picture(&pixels, image.width, image.height);
    let (rest, pixels): (Vec<Point3<f32>>, Vec<_>) =
        region.iter().copied().zip(pixels).filter(|(p, _)| !taken.contains(&bits(p))).unzip();
    let colours = colours_at(&pixels, image, PIXEL_NOISE_REACH);
    let its = colour_of_the_whole(part, image, calibration);
    let not_its =
        |c: &Option<[f32; 2]>| its.as_ref().is_none_or(|its| c.is_some_and(|c| !its.holds(c)));
    let (rest, (pixels, colours)): (Vec<Point3<f32>>, (Vec<_>, Vec<_>)) = rest
        .into_iter()
        .zip(pixels.into_iter().zip(colours))
        .filter(|(_, (_, c))| not_its(c))
        .unzip();
    // What stays of its outline is a strip of the picture narrower than any tag seen there.
    let (rest, colours) = if dense {
        let off = off_the_strips(&pixels, image.width, image.height, PIXEL_NOISE_REACH);
        rest.into_iter().zip(colours).zip(off).filter(|(_, off)| *off).map(|(pc, _)| pc).unzip()
    } else {
        (rest, colours)
    };
    let rest =
        match tag_coloured(&rest, &colours, &core_of(&rest, target, params), params.voxel_size) {
            Some(split) => split.kept,
            None => rest,
        };
    // A part is taken beside the red thing for a colour of its own, which takes a core's
    // points to tell through the noise; fewer are a scrap of the red thing's outline.
    join(components_of(&rest, target, params))
        .into_iter()
        .filter(|c| c.points >= core_points(params) && bound.holds(c))
        .collect()
}

/// The colour of all of `part`'s points.
fn colour_of_the_whole(
    part: &Component,
    image: &ColorImage,
    calibration: &CameraCalibration,
) -> Option<ColourOf> {
    let colours = colours_around(&part.members, image, calibration, PIXEL_NOISE_REACH);
    let all: Vec<usize> = (0..colours.len()).collect();
    ColourOf::of(&colours, &all)
}

/// The part of `parts` nearest the target that is large enough to be a tag.
fn nearest_part<'a>(parts: &'a [Component], params: &TagSearchParams) -> Option<&'a Component> {
    parts
        .iter()
        .filter(|p| p.points >= params.min_points)
        .min_by(|a, b| a.distance_to_target.total_cmp(&b.distance_to_target))
}

/// Where in `parts` their [`nearest_part`] is, and why it is no tag; `None` when it may be one,
/// or there is none.
fn nearest_too_large(
    parts: &[Component],
    params: &TagSearchParams,
    bound: &TagBound,
) -> Option<(usize, TooLarge)> {
    let nearest = nearest_part(parts, params)?;
    let i = parts.iter().position(|p| std::ptr::eq(p, nearest))?;
    Some((i, bound.too_large(nearest)?))
}

/// Which second colours divide a part.
#[derive(Clone, Copy)]
enum OtherColour {
    /// Any: the part is larger than any tag, so it holds something else.
    Any,
    /// Only a colour the search takes for a tag's. A region no larger than a tag holds a second
    /// thing only when that is red too: its points of another colour are where the mask's
    /// closing filled the tag's outline, or where the laser's returns on the tag's edge fall on
    /// the wall's pixels, and they belong to the tag.
    Red,
}

/// `part` divided by its voxels' colours when they fall into two (a red plastic of nearly the
/// tag's colour against it), into the parts of its part nearest the target's colour.
#[allow(clippy::too_many_arguments)]
fn of_two_colours(
    part: &Component,
    image: &ColorImage,
    calibration: &CameraCalibration,
    target: &Point3<f64>,
    params: &TagSearchParams,
    other: OtherColour,
    notes: &mut Vec<String>,
) -> Option<Vec<Component>> {
    let colours = colours_of(&part.members, image, calibration);
    let core = core_of(&part.members, target, params);
    let half =
        of_the_core_cluster(&part.members, &colours, &core, params.voxel_size, params.min_points)?;
    if let OtherColour::Red = other
        && params.thresholds.chroma_distance(half.other) > RED_REACH_SPREADS * half.spread
    {
        return beyond_the_closing(part, &half.kept, image, calibration, target, params, notes);
    }
    notes.push(format!(
        "a part {:.0} cm across is of two colours voxel by voxel ({:.3} apart on the chroma \
         disc, {:.0} times their spread): {} of its {} points have the colour of its part \
         nearest the target",
        part.radius * 200.0,
        half.distance,
        half.distance / half.spread,
        half.kept.len(),
        part.points,
    ));
    let kept: Vec<Point3<f32>> = half.kept.iter().map(|&i| part.members[i]).collect();
    Some(components_of(&kept, target, params))
}

/// `part` without its points of a colour the search does not take that lie beyond the mask's
/// closing from every point of its tag's colour (`kept`), when there are enough of them to be
/// a thing. The closing fills a tag's outline and its folds with pixels of other colours, and
/// those points belong to the tag. Points further from the tag's colour were not filled in for
/// it: a thin thing one or two pixels wide closed over between the pixels of a red-enough
/// background (a lamp's pull chain before a wooden wall), or a wood whose colour the search
/// lets in only here and there. Only a cloud dense in the picture is judged so: a laser's beams
/// land pixels apart, and the tag's own points of another colour may lie as far from its red
/// ones.
fn beyond_the_closing(
    part: &Component,
    kept: &[usize],
    image: &ColorImage,
    calibration: &CameraCalibration,
    target: &Point3<f64>,
    params: &TagSearchParams,
    notes: &mut Vec<String>,
) -> Option<Vec<Component>> {
    let pixels = pixels_of(&part.members, image, calibration);
    if !dense_in_the_picture(&pixels, image.width, image.height) {
        return None;
    }
    let mut red = Mask::new(image.width as usize, image.height as usize);
    for &(x, y) in kept.iter().filter_map(|&i| pixels[i].as_ref()) {
        red.set(x as usize, y as usize, true);
    }
    let within = red.dilate(params.close_radius_px);
    let near_red =
        |px: &Option<(u32, u32)>| px.is_none_or(|(x, y)| within.get(x as usize, y as usize));
    let stays: Vec<Point3<f32>> =
        part.members.iter().zip(&pixels).filter(|(_, px)| near_red(px)).map(|(p, _)| *p).collect();
    let beyond = part.members.len() - stays.len();
    if beyond < params.min_points {
        return None;
    }
    notes.push(format!(
        "a part {:.0} cm across has {beyond} of its {} points of a colour the search does not \
         take further in the picture than its closing ({} pixels) from every point of its own \
         colour: another thing, not the tag's outline the closing filled",
        part.radius * 200.0,
        part.points,
        params.close_radius_px,
    ));
    Some(components_of(&stays, target, params))
}

/// `part` divided by its voxels' distances from the plane its part nearest the target lies on,
/// when they fall into two (a red plastic of the tag's colour standing a few millimetres
/// prouder or flatter than the tag on the same surface).
fn of_two_surfaces(
    part: &Component,
    target: &Point3<f64>,
    params: &TagSearchParams,
    notes: &mut Vec<String>,
) -> Option<Vec<Component>> {
    // The tag and the thing beside it lie on one surface and face the same way: the normal of
    // the whole part is theirs, held steady by the larger thing's breadth (a tag-sized core's
    // own tilts by a degree in the noise, a millimetre across a box).
    let members: Vec<Point3<f64>> = part.members.iter().map(|p| p.cast::<f64>()).collect();
    let (centre, normal, _) = plane_through(&members)?;
    let core = core_of(&part.members, target, params);
    let offset = |p: &Point3<f32>| (p.cast::<f64>().coords - centre).dot(&normal);
    let offsets: Vec<Option<[f32; 2]>> =
        part.members.iter().map(|p| Some([offset(p) as f32, 0.0])).collect();
    // Grouped by their cells on the surface, not by voxels of space: a voxel's face cuts
    // through a surface's noise and would sort its points by the very distance measured.
    let on_surface: Vec<Point3<f32>> =
        part.members.iter().map(|p| (p.cast::<f64>() - normal * offset(p)).cast::<f32>()).collect();
    let half =
        of_the_core_cluster(&on_surface, &offsets, &core, params.voxel_size, params.min_points)?;
    notes.push(format!(
        "a part {:.0} cm across lies on two surfaces voxel by voxel ({:.1} mm apart, {:.0} times \
         their spread): {} of its {} points lie on the surface of its part nearest the target",
        part.radius * 200.0,
        half.distance * 1e3,
        half.distance / half.spread,
        half.kept.len(),
        part.points,
    ));
    let kept: Vec<Point3<f32>> = half.kept.iter().map(|&i| part.members[i]).collect();
    Some(components_of(&kept, target, params))
}

/// The piece of `part`'s surface in `region` that a disc a little wider than the home's widest
/// tag cannot reach, when the home's tags' sizes are known: a tag standing out of a red thing
/// of nearly its colour beside it ([`super::tag_shape`]).
fn standing_out(
    part: &Component,
    region: &[Point3<f32>],
    target: &Point3<f64>,
    params: &TagSearchParams,
    notes: &mut Vec<String>,
) -> Option<Vec<Component>> {
    let half_width = params.widest_tag_half_width?;
    let Surface { centre, normal, points: on_surface } = region_on_the_surface_of(part, region)?;
    let piece = out_of_reach_of_a_disc(&on_surface, &centre, &normal, half_width, target)?;
    notes.push(format!(
        "a part {:.0} cm across has a piece no disc {:.0} cm wide reaches, no tag in the home \
         being wider than {:.0} cm: {} of the {} points of its region on its surface",
        part.radius * 200.0,
        piece.disc * 100.0,
        half_width * 200.0,
        piece.kept.len(),
        on_surface.len(),
    ));
    let kept: Vec<Point3<f32>> = piece.kept.iter().map(|&i| on_surface[i]).collect();
    Some(components_of(&kept, target, params))
}

/// The points of `part`'s surface in `region` in the rectangle of a registered tag's size that
/// borders nothing red on three sides and the rest on the fourth, near the target: a tag lying
/// against a red thing of nearly its colour by a side as long as the disc of
/// [`standing_out`] is wide ([`super::tag_against_a_side`]).
#[allow(clippy::too_many_arguments)]
fn lying_against_it(
    part: &Component,
    region: &[Point3<f32>],
    image: &ColorImage,
    calibration: &CameraCalibration,
    target: &Point3<f64>,
    params: &TagSearchParams,
    notes: &mut Vec<String>,
) -> Option<Vec<Component>> {
    if params.home_tags.is_empty() {
        return None;
    }
    let Surface { centre, normal, points: on_surface } = region_on_the_surface_of(part, region)?;
    // Red here is the part's own colour, which the tag and the thing against it share: a wood
    // past the tag's free sides that the search's colours let in is not the thing.
    let its = colour_of_the_whole(part, image, calibration)?;
    let colours = colours_around(&on_surface, image, calibration, PIXEL_NOISE_REACH);
    let on_surface: Vec<Point3<f32>> = on_surface
        .into_iter()
        .zip(colours)
        .filter(|(_, c)| c.is_some_and(|c| its.holds(c)))
        .map(|(p, _)| p)
        .collect();
    // A side is free only where the picture shows none of that colour either: a thing of it
    // nearer the camera (a tube before the fabric it touches) hides the surface without lying
    // on it.
    let pixel_of = pixel_finder(image, calibration);
    let seen_red = |p: &Point3<f64>| {
        pixel_of(p)
            .is_some_and(|(x, y)| its.holds(mean_colour_around(image, x, y, PIXEL_NOISE_REACH)))
    };
    let sizes = &params.home_tags;
    let reach = params.max_tag_radius;
    let found = against_a_side(&on_surface, &centre, &normal, sizes, target, reach, &seen_red)?;
    notes.push(format!(
        "a part {:.0} cm across has a tag's rectangle ({:.1} × {:.1} cm, as registered) \
         against one side of it, nothing of their colour past its other three: {} of the {} \
         points of its region on its surface",
        part.radius * 200.0,
        found.size.width * 100.0,
        found.size.height * 100.0,
        found.kept.len(),
        on_surface.len(),
    ));
    let kept: Vec<Point3<f32>> = found.kept.iter().map(|&i| on_surface[i]).collect();
    Some(components_of(&kept, target, params))
}

/// A part's surface and the points of its region on it.
struct Surface {
    centre: Vector3<f64>,
    normal: Vector3<f64>,
    points: Vec<Point3<f32>>,
}

/// The plane through `part`, and the whole of `region` within the part's own reach of it,
/// whatever its colour: the colour division keeps of a red plastic nearly the tag's colour only
/// the pixels the noise moved toward it.
fn region_on_the_surface_of(part: &Component, region: &[Point3<f32>]) -> Option<Surface> {
    let members: Vec<Point3<f64>> = part.members.iter().map(|p| p.cast::<f64>()).collect();
    let (centre, normal, _) = plane_through(&members)?;
    let offset = |p: &Point3<f64>| (p.coords - centre).dot(&normal);
    let band = members.iter().map(|p| offset(p).abs()).fold(0.0, f64::max);
    let points: Vec<Point3<f32>> =
        region.iter().filter(|p| offset(&p.cast::<f64>()).abs() <= band).copied().collect();
    Some(Surface { centre, normal, points })
}

/// The plane through `points` (their centre and the normal of least scatter), and the standard
/// deviation of the points about it; `None` for fewer than three.
fn plane_through(points: &[Point3<f64>]) -> Option<(Vector3<f64>, Vector3<f64>, f64)> {
    if points.len() < 3 {
        return None;
    }
    let centre = points.iter().map(|p| p.coords).sum::<Vector3<f64>>() / points.len() as f64;
    let scatter = points.iter().fold(Matrix3::zeros(), |m, p| {
        let d = p.coords - centre;
        m + d * d.transpose()
    });
    let eigen = scatter.symmetric_eigen();
    let smallest = eigen.eigenvalues.imin();
    let normal: Vector3<f64> = eigen.eigenvectors.column(smallest).into();
    let noise = (eigen.eigenvalues[smallest].max(0.0) / points.len() as f64).sqrt();
    Some((centre, normal, noise))
}

/// The points of `points` that have the colour of those nearest `anchor` (all of them when
/// they are one colour): a tag's own pixels, without the wood or the fringe it touches.
pub(crate) fn of_the_colour_at(
    points: &[Point3<f32>],
    image: &ColorImage,
    calibration: &CameraCalibration,
    anchor: &Point3<f64>,
    params: &TagSearchParams,
) -> Vec<Point3<f32>> {
    let colours = colours_of(points, image, calibration);
    match tag_coloured(points, &colours, &core_of(points, anchor, params), params.voxel_size) {
        Some(split) => split.kept,
        None => points.to_vec(),
    }
}

/// What is said of the red region nearest the target when it is too large to be a tag: why
/// no component was taken (`taken` is `None`), or why the tag `taken` beside it, not it, is
/// the one the person pointed at.
pub(super) fn too_large_nearest(
    components: &[Component],
    taken: Option<&TagDetection>,
    params: &TagSearchParams,
    bound: &TagBound,
) -> Option<String> {
    let nearest = components
        .iter()
        .filter(|c| c.points >= params.min_points && c.distance_to_target <= params.max_distance)
        .min_by(|a, b| a.distance_to_target.total_cmp(&b.distance_to_target))?;
    let too_large = bound.too_large(nearest)?;
    let region = format!(
        "the red region nearest the target ({} points, {:.0} cm from it) is {too_large}",
        nearest.points,
        nearest.distance_to_target * 100.0,
    );
    Some(match taken {
        None => {
            let divisions = match params.widest_tag_half_width {
                Some(_) => "neither its colours, its surfaces nor its shape divide it",
                None => "neither its colours nor its surfaces divide it",
            };
            format!("{region}, and {divisions}, so it is not taken for a tag")
        }
        Some(tag) => format!(
            "{region}: the tag-sized part beside it ({} points, {:.0} cm from the target) is \
             taken for the tag",
            tag.points,
            tag.distance_to_target * 100.0,
        ),
    })
}

/// The points of a part that stand for the tag: those within `fragment_gap` (the reach of one
/// tag's own fragments) of the part's point nearest the target, and at least as many as a tag
/// has at the least, three times over, so that their colour and surface are measured through
/// the noise and span more than one of the laser's scan lines.
fn core_of(points: &[Point3<f32>], target: &Point3<f64>, params: &TagSearchParams) -> Vec<usize> {
    let Some(&seed) = nearest(points, target, 1).first() else { return Vec::new() };
    let seed = points[seed].cast::<f64>();
    let least = core_points(params);
    let within: Vec<usize> = (0..points.len())
        .filter(|&i| (points[i].cast::<f64>() - seed).norm() <= params.fragment_gap)
        .collect();
    if within.len() >= least { within } else { nearest(points, &seed, least) }
}

/// The fewest points a core holds: as many as a tag has at the least, three times over.
fn core_points(params: &TagSearchParams) -> usize {
    3 * params.min_points.max(3)
}

fn components_of(
    points: &[Point3<f32>],
    target: &Point3<f64>,
    params: &TagSearchParams,
) -> Vec<Component> {
    OccupancyGrid::new(points, params.voxel_size).connected_components(target)
}

/// Indices of the `n` points nearest `target` (all of them when there are fewer).
fn nearest(points: &[Point3<f32>], target: &Point3<f64>, n: usize) -> Vec<usize> {
    let mut by_distance: Vec<(f64, usize)> = points
        .iter()
        .enumerate()
        .map(|(i, p)| ((p.cast::<f64>() - target).norm_squared(), i))
        .collect();
    if n < by_distance.len() {
        by_distance.select_nth_unstable_by(n, |a, b| a.0.total_cmp(&b.0));
        by_distance.truncate(n);
    }
    by_distance.into_iter().map(|(_, i)| i).collect()
}

/// The points of a part on the surface the part's points nearest the target lie on.
struct SurfaceCut {
    kept: Vec<Point3<f32>>,
    /// Half the band's width, metres.
    band: f64,
}

/// Fits a plane to the part's points nearest the target and keeps the part's points within
/// `SURFACE_BAND_SIGMAS` standard deviations of those points about it; `None` when that keeps
/// them all.
fn on_the_nearest_surface(
    part: &Component,
    target: &Point3<f64>,
    params: &TagSearchParams,
) -> Option<SurfaceCut> {
    let core: Vec<Point3<f64>> = core_of(&part.members, target, params)
        .into_iter()
        .map(|i| part.members[i].cast::<f64>())
        .collect();
    let (centre, normal, noise) = plane_through(&core)?;
    // The band is never thinner than the grid resolves.
    let band = (SURFACE_BAND_SIGMAS * noise).max(f64::from(params.voxel_size) / 2.0);
    let in_band: Vec<Point3<f32>> = part
        .members
        .iter()
        .filter(|p| (p.cast::<f64>().coords - centre).dot(&normal).abs() <= band)
        .copied()
        .collect();
    let kept = without_crossing_strips(&in_band, &centre.into(), &normal, band, params);
    // A surface that keeps nothing of the part is not the one its core lies on: a core too
    // thin for the opening (a tube seen from its side) is no surface to cut to.
    (!kept.is_empty() && kept.len() < part.members.len()).then_some(SurfaceCut { kept, band })
}

/// The band of a surface cuts any surface crossing it (the side of a bin standing on it) to a
/// strip as wide as the band. Seen along the normal, such a strip is a line `2 band` wide, and
/// a tag is wider than that both ways: an opening of the points' cells on the surface as wide
/// as the band removes the strips and keeps the tag. The cells are closed by one first, so the
/// gaps between the laser's scan lines do not open a tag up.
fn without_crossing_strips(
    points: &[Point3<f32>],
    centre: &Point3<f64>,
    normal: &Vector3<f64>,
    band: f64,
    params: &TagSearchParams,
) -> Vec<Point3<f32>> {
    let cell = f64::from(params.voxel_size);
    let u = normal.cross(&Vector3::z()).try_normalize(1e-9).unwrap_or_else(Vector3::x);
    let v = normal.cross(&u);
    let on_surface: Vec<[i64; 2]> = points
        .iter()
        .map(|p| {
            let d = p.cast::<f64>() - centre;
            [(d.dot(&u) / cell).floor() as i64, (d.dot(&v) / cell).floor() as i64]
        })
        .collect();
    let radius = (band / cell).ceil() as usize;
    let margin = (radius + 2) as i64;
    let (Some(lo_u), Some(hi_u), Some(lo_v), Some(hi_v)) = (
        on_surface.iter().map(|c| c[0]).min(),
        on_surface.iter().map(|c| c[0]).max(),
        on_surface.iter().map(|c| c[1]).min(),
        on_surface.iter().map(|c| c[1]).max(),
    ) else {
        return Vec::new();
    };
    let (width, height) =
        ((hi_u - lo_u + 1 + 2 * margin) as usize, (hi_v - lo_v + 1 + 2 * margin) as usize);
    let at = |c: &[i64; 2]| ((c[0] - lo_u + margin) as usize, (c[1] - lo_v + margin) as usize);
    let mut occupied = Mask::new(width, height);
    for c in &on_surface {
        let (x, y) = at(c);
        occupied.set(x, y, true);
    }
    let opened = occupied.close(1).open(radius);
    points
        .iter()
        .zip(&on_surface)
        .filter(|(_, c)| {
            let (x, y) = at(c);
            opened.get(x, y)
        })
        .map(|(p, _)| *p)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::perception::hsv::HsvThresholds;
    use crate::perception::tag::choose_tag;
    use crate::perception::tag_sighting::TagSighting;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// A towel 20 × 15 cm on the plane x = 1 (noise 2 mm), and the side of a bin standing
    /// across that plane along one of its edges: 60 cm deep toward the robot, 45 cm tall.
    fn towel_and_bin_side(rng: &mut ChaCha8Rng) -> (Vec<Point3<f32>>, Vec<Point3<f32>>) {
        let mut noise = || rng.random_range(-0.002f32..0.002);
        let mut towel = Vec::new();
        for i in 0..40 {
            for j in 0..30 {
                let (y, z) = (i as f32 * 0.005 - 0.1, j as f32 * 0.005 - 0.075);
                towel.push(Point3::new(1.0 + noise(), y, z));
            }
        }
        let mut side = Vec::new();
        for i in 0..120 {
            for j in 0..90 {
                let (x, z) = (1.0 - i as f32 * 0.005, j as f32 * 0.005 - 0.45);
                side.push(Point3::new(x + noise(), 0.1, z));
            }
        }
        (towel, side)
    }

    /// A 6 × 6 cm tag on the plane x = 1 and a 20 × 20 cm red box beside it whose front stands
    /// `step` metres prouder, toward the robot; each point scattered ±3 mm along x, about a
    /// structured-light camera's noise at 1.5 m, 16 points a 1 cm voxel.
    fn tag_and_box(step: f32, rng: &mut ChaCha8Rng) -> (Vec<Point3<f32>>, Vec<Point3<f32>>) {
        let (mut tag, mut red_box) = (Vec::new(), Vec::new());
        for i in 0..104 {
            for j in 0..80 {
                let (y, z) = (i as f32 * 0.0025, j as f32 * 0.0025);
                let noise = rng.random_range(-0.003f32..0.003);
                if y < 0.06 && z < 0.06 {
                    tag.push(Point3::new(1.0 + noise, y, z));
                } else if y >= 0.06 {
                    red_box.push(Point3::new(1.0 - step + noise, y, z));
                }
            }
        }
        (tag, red_box)
    }

    fn region_of(points: &[Point3<f32>], target: &Point3<f64>) -> Component {
        let params = TagSearchParams::default();
        let mut parts = OccupancyGrid::new(points, params.voxel_size).connected_components(target);
        assert_eq!(parts.len(), 1, "tag and box touch");
        parts.remove(0)
    }

    /// What the search takes in `region`, seen by `looking_along_x` in `image` and pointed at
    /// `target`, and what it says.
    fn chosen_in(
        region: Component,
        image: &ColorImage,
        target: &Point3<f64>,
        params: &TagSearchParams,
    ) -> (Option<TagSighting>, Vec<String>) {
        let calibration = looking_along_x();
        let bound = TagBound::new(params, &calibration);
        let mut notes = Vec::new();
        let bounded = bound_tags(
            vec![region],
            image,
            &calibration,
            target,
            params,
            &bound,
            &|parts| parts,
            &mut notes,
        );
        (choose_tag(bounded, params, &bound), notes)
    }

    #[test]
    fn a_red_box_a_few_millimetres_prouder_than_the_tag_is_parted_from_it() {
        let params = TagSearchParams::default();
        let target = Point3::new(1.0, 0.02, 0.03);
        for seed in 0..10 {
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            let (tag, red_box) = tag_and_box(0.004, &mut rng);
            let all: Vec<Point3<f32>> = tag.iter().chain(&red_box).copied().collect();
            let mut notes = Vec::new();
            let parts = of_two_surfaces(&region_of(&all, &target), &target, &params, &mut notes)
                .expect("two surfaces");
            let nearest = parts
                .iter()
                .min_by(|a, b| a.distance_to_target.total_cmp(&b.distance_to_target))
                .unwrap();
            let of_the_box = nearest.members.iter().filter(|p| p.y >= 0.07).count();
            assert_eq!(of_the_box, 0, "seed {seed}: none of the box beyond its edge stays");
            // All but the cells along the box's edge, whose means pool with the box's.
            assert!(nearest.points >= tag.len() * 8 / 10, "seed {seed}: {}", nearest.points);
            assert!(notes[0].contains("two surfaces"), "{notes:?}");
        }
    }

    #[test]
    fn a_red_box_flush_with_the_tag_is_one_surface() {
        let params = TagSearchParams::default();
        let target = Point3::new(1.0, 0.02, 0.03);
        for seed in 0..10 {
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            let (tag, red_box) = tag_and_box(0.0, &mut rng);
            let all: Vec<Point3<f32>> = tag.iter().chain(&red_box).copied().collect();
            let region = region_of(&all, &target);
            let divided = of_two_surfaces(&region, &target, &params, &mut Vec::new());
            assert!(divided.is_none(), "seed {seed}");
        }
    }

    #[test]
    fn the_surface_nearest_the_target_keeps_the_towel_and_cuts_the_crossing_side() {
        let params = TagSearchParams::default();
        let target = Point3::new(1.0, 0.01, 0.02);
        for seed in 0..20 {
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            let (towel, side) = towel_and_bin_side(&mut rng);
            let all: Vec<Point3<f32>> = towel.iter().chain(&side).copied().collect();
            let part = OccupancyGrid::new(&all, params.voxel_size)
                .connected_components(&target)
                .into_iter()
                .max_by_key(|c| c.points)
                .unwrap();
            assert!(
                part.radius > params.max_tag_radius,
                "seed {seed}: the two join, and are large"
            );
            let cut = on_the_nearest_surface(&part, &target, &params).expect("something is cut");
            let kept_side = cut.kept.iter().filter(|p| p.x < 0.98).count();
            assert_eq!(kept_side, 0, "seed {seed}: none of the side away from the surface stays");
            // The strip of the side within the band, below the towel, is opened away.
            let strip = cut.kept.iter().filter(|p| p.z < -0.1).count();
            assert_eq!(strip, 0, "seed {seed}: the side's strip in the band stays");
            assert!(
                cut.kept.len() >= towel.len() * 9 / 10,
                "seed {seed}: {} of the towel's {}",
                cut.kept.len(),
                towel.len()
            );
            assert!(cut.band < 0.012, "seed {seed}: a band of {:.1} mm", cut.band * 1e3);
        }
    }

    /// A camera at the origin looking along the base's x axis, one pixel a millimetre at 1 m,
    /// seeing 40 × 40 cm there.
    fn looking_along_x() -> CameraCalibration {
        let camera_axes = Matrix3::new(0.0, 0.0, 1.0, -1.0, 0.0, 0.0, 0.0, -1.0, 0.0);
        let rotation = nalgebra::Rotation3::from_matrix_unchecked(camera_axes);
        CameraCalibration {
            intrinsics: crate::hal::CameraIntrinsics {
                width: 400,
                height: 400,
                fx: 1000.0,
                fy: 1000.0,
                cx: 200.0,
                cy: 200.0,
            },
            base_from_camera: nalgebra::Isometry3::from_parts(
                nalgebra::Translation3::identity(),
                rotation.into(),
            ),
        }
    }

    /// What the camera sees: to the right of the middle column (base y < 0) the tag's red, to
    /// its left `left`; each pixel's blue scattered as a camera's noise scatters it.
    fn picture(left: [u8; 3]) -> ColorImage {
        let mut image = ColorImage::new(400, 400);
        for y in 0..400u32 {
            for x in 0..400u32 {
                let [r, g, b] = if x > 200 { [200, 30, 20] } else { left };
                let blue = if (x + y) % 2 == 0 { b } else { b + 20 };
                let i = (y as usize * 400 + x as usize) * 3;
                image.rgb[i..i + 3].copy_from_slice(&[r, g, blue]);
            }
        }
        image
    }

    fn bounded_with(image: &ColorImage, target: &Point3<f64>) -> (Vec<Component>, Vec<String>) {
        let params = TagSearchParams::default();
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let (towel, _) = towel_and_bin_side(&mut rng);
        let components = components_of(&towel, target, &params);
        assert!(components.iter().all(|c| c.radius <= params.max_tag_radius));
        let mut notes = Vec::new();
        let calibration = looking_along_x();
        let bounded = bound_tags(
            components,
            image,
            &calibration,
            target,
            &params,
            &TagBound::new(&params, &calibration),
            &|parts| parts,
            &mut notes,
        );
        (bounded, notes)
    }

    #[test]
    fn a_region_the_size_of_a_tag_and_of_one_colour_is_left_alone() {
        let target = Point3::new(1.0, -0.05, 0.0);
        let (bounded, notes) = bounded_with(&picture([200, 30, 20]), &target);
        assert_eq!(bounded.len(), 1);
        assert_eq!(bounded[0].points, 40 * 30);
        assert!(notes.is_empty(), "{notes:?}");
    }

    #[test]
    fn a_region_the_size_of_a_tag_whose_second_colour_is_not_red_is_left_alone() {
        // Where the laser's returns on a tag's edge meet the wall's pixels.
        let target = Point3::new(1.0, -0.05, 0.0);
        let (bounded, notes) = bounded_with(&picture([120, 100, 90]), &target);
        assert_eq!(bounded.len(), 1);
        assert_eq!(bounded[0].points, 40 * 30);
        assert!(notes.is_empty(), "{notes:?}");
    }

    #[test]
    fn a_region_the_size_of_a_tag_and_of_two_colours_is_divided() {
        // The towel's right half is the tag; its left half a paler red plastic against it.
        let target = Point3::new(1.0, -0.05, 0.0);
        let (bounded, notes) = bounded_with(&picture([185, 50, 45]), &target);
        let nearest = bounded
            .iter()
            .min_by(|a, b| a.distance_to_target.total_cmp(&b.distance_to_target))
            .unwrap();
        let plastic = nearest.members.iter().filter(|p| p.y > 0.01).count();
        assert_eq!(plastic, 0, "{notes:?}");
        assert!(nearest.points >= 20 * 30 * 9 / 10, "{} points", nearest.points);
        assert!(notes.iter().any(|n| n.contains("two colours")), "{notes:?}");
    }

    /// A 6 × 6 cm tag (base y < 0, the picture's right) against the side of a red box 20 cm
    /// wide and 40 cm tall on the plane x = 1 (y ≥ 0, the picture's left), the tag `step`
    /// metres behind the box's front; 16 points a 1 cm voxel. The box's side, facing the tag,
    /// is seen too (2 mm on the box's side of the tag's edge: its own pixels).
    fn tag_against_a_box(step: f32) -> (Vec<Point3<f32>>, Vec<Point3<f32>>) {
        let (mut tag, mut red_box) = (Vec::new(), Vec::new());
        let at = |k: i32| k as f32 * 0.0025 + 0.00125;
        for i in -24..80 {
            for j in -80..80 {
                let (y, z) = (at(i), at(j));
                if y < 0.0 && z.abs() < 0.03 {
                    tag.push(Point3::new(1.0 + step, y, z));
                } else if y >= 0.0 {
                    red_box.push(Point3::new(1.0, y, z));
                }
            }
            let side = (0..(step / 0.0025) as i32).map(|k| Point3::new(1.0 + at(k), 0.002, at(i)));
            red_box.extend(side);
        }
        (tag, red_box)
    }

    /// As [`picture`], each pixel's channels scattered at random by up to 8 either way.
    fn noisy_picture(left: [u8; 3]) -> ColorImage {
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        let mut image = picture(left);
        for v in &mut image.rgb {
            *v = (i16::from(*v) + rng.random_range(-8i16..=8)).clamp(0, 255) as u8;
        }
        image
    }

    #[test]
    fn a_tag_beside_a_red_box_nearer_the_pointed_spot_is_found_beside_it() {
        // Pointed 4 cm into the box, 3 cm prouder than the tag and 8 cm from its middle: the
        // division anchored there keeps the box's front, too large to be a tag, and its side
        // and the tag are left beside it.
        let (tag, red_box) = tag_against_a_box(0.03);
        let found = found_beside_a_box(&tag, &red_box, &noisy_picture([185, 50, 45]));
        assert!((found.centroid - Point3::new(1.03, -0.03, 0.0)).norm() < 0.005, "{found:?}");
        assert!(found.points >= tag.len() * 9 / 10, "{} of {}", found.points, tag.len());
    }

    #[test]
    fn a_pull_chain_the_closing_took_in_is_not_part_of_the_tube() {
        // A lamp's 13 × 3 cm foam tube hanging from a dark chain two pixels wide, 20 cm of it
        // above the tube, before a wooden wall the search lets in: the mask's closing takes
        // the chain's pixels in between the wall's, and the chain's points, at the tube's
        // depth, join it. Sizes unknown, so the region is no larger than a tag.
        let tube = OnThePlane { y: -0.015..0.015, z: -0.065..0.065, colour: [200, 30, 20] };
        let chain = OnThePlane { y: -0.001..0.001, z: 0.065..0.265, colour: [40, 40, 45] };
        let target = Point3::new(1.0, 0.0, 0.02);
        let (region, image, tube) = tag_and_thing(31, &tube, &chain, &target);
        let params = TagSearchParams::default();
        let (sighting, notes) = chosen_in(region, &image, &target, &params);
        let Some(TagSighting::Found(found)) = sighting else {
            panic!("no tube: {notes:?}");
        };
        // Kept, the chain lifts the middle by 9 mm.
        assert!((found.centroid - Point3::new(1.0, 0.0, 0.0)).norm() < 0.003, "{found:?}");
        // The tube, and the chain in the voxels beside the tube's, whose colour is pooled with
        // the tube's: 2 cm of it at most, two pixels wide.
        assert!(found.points <= tube.len() + 2 * 20, "{} of {}", found.points, tube.len());
        let said = notes.join(" ");
        assert!(said.contains("another thing, not the tag's outline"), "{said}");
    }

    #[test]
    fn a_fabric_beside_a_tube_reaching_no_further_than_it_is_not_taken_for_it() {
        // A lamp's foam tube, 13 × 3 cm as registered, and a red fabric 8 cm square hanging
        // against its side, pointed 3 cm into the fabric. Together they reach 8.6 cm from their
        // middle and each part less, within the tube's 6.7 cm and a fragment's gap: only its
        // width, 8 cm where the tube's is 3, tells the fabric from a tag.
        let tube = OnThePlane { y: -0.03..0.0, z: -0.065..0.065, colour: [200, 30, 20] };
        let fabric = OnThePlane { y: 0.0..0.08, z: -0.02..0.06, colour: [185, 50, 45] };
        let registered = pps_schema::TagSize { width: 0.13, height: 0.03 };
        let target = Point3::new(1.0, 0.03, 0.02);
        let (region, image, of_the_tube) = tag_and_thing(17, &tube, &fabric, &target);
        let reach = TagSearchParams::default().for_home_tags([registered]).max_tag_radius;
        assert!(region.radius <= reach, "{} cm", region.radius * 100.0);
        let (found, notes) = found_in(region, &image, registered, &target);
        assert!((found.centroid - Point3::new(1.0, -0.015, 0.0)).norm() < 0.005, "{found:?}");
        // Less the pixels along the fabric, whose colour the camera mixes with the tube's.
        let tube_points = of_the_tube.len();
        assert!(found.points >= tube_points * 4 / 5, "{} of {tube_points}", found.points);
        let said = notes.join(" ");
        assert!(said.contains("wide as the camera sees it, wider than any tag"), "{said}");
    }

    /// The tag found among `tag` and `red_box`, seen in `image` and pointed at 4 cm into the
    /// box, with no tag reaching more than 8 cm from its middle.
    fn found_beside_a_box(
        tag: &[Point3<f32>],
        red_box: &[Point3<f32>],
        image: &ColorImage,
    ) -> TagDetection {
        let params = TagSearchParams { max_tag_radius: 0.08, ..TagSearchParams::default() };
        let target = Point3::new(1.0, 0.04, 0.0);
        let all: Vec<Point3<f32>> = tag.iter().chain(red_box).copied().collect();
        match chosen_in(region_of(&all, &target), image, &target, &params).0 {
            Some(TagSighting::Found(found)) => found,
            other => panic!("the tag beside the box: {other:?}"),
        }
    }

    /// A 6 × 6 cm tag (base y < 0) flush with the front of a red box 15 cm wide and 30 cm tall
    /// (y ≥ 0) on the plane x = 1, as a depth camera samples them: a point a pixel. The box's
    /// outline, a pixel wide, is of neither colour, as the camera mixes an edge with what lies
    /// behind it; the wall around is grey. The points, and the picture with each pixel's
    /// channels scattered by up to 8 either way.
    fn tag_flush_with_an_outlined_box() -> (Vec<Point3<f32>>, Vec<Point3<f32>>, ColorImage) {
        let (mut tag, mut red_box) = (Vec::new(), Vec::new());
        let image = the_plane_seen(13, |point| {
            let (y, z) = (f64::from(point.y), f64::from(point.z));
            let on_box = (0.0..0.15).contains(&y) && z.abs() < 0.15;
            let outline = on_box && (!(0.001..=0.149).contains(&y) || z.abs() > 0.149);
            if (-0.06..0.0).contains(&y) && z.abs() < 0.03 {
                tag.push(point);
                [200, 30, 20]
            } else if outline {
                red_box.push(point);
                [150, 70, 60]
            } else if on_box {
                red_box.push(point);
                [185, 50, 45]
            } else {
                [120, 110, 100]
            }
        });
        (tag, red_box, image)
    }

    /// A rectangle of the plane x = 1, its `y` and `z` in metres, of one colour.
    struct OnThePlane {
        y: std::ops::Range<f64>,
        z: std::ops::Range<f64>,
        colour: [u8; 3],
    }

    /// The region a tag and a red thing against it make on the plane x = 1, the plane's
    /// picture (`seed` scattering its pixels) and the tag's own points.
    fn tag_and_thing(
        seed: u64,
        tag: &OnThePlane,
        thing: &OnThePlane,
        target: &Point3<f64>,
    ) -> (Component, ColorImage, Vec<Point3<f32>>) {
        let (mut of_the_tag, mut all) = (Vec::new(), Vec::new());
        let image = the_plane_seen(seed, |point| {
            let (y, z) = (f64::from(point.y), f64::from(point.z));
            let on = |r: &OnThePlane| r.y.contains(&y) && r.z.contains(&z);
            if on(tag) {
                of_the_tag.push(point);
                all.push(point);
                tag.colour
            } else if on(thing) {
                all.push(point);
                thing.colour
            } else {
                [120, 110, 100]
            }
        });
        (region_of(&all, target), image, of_the_tag)
    }

    /// The tag the search finds in `region` on the plane x = 1, seen in `image`, the home's
    /// tags of `registered` size, pointed at `target`; and the notes. Panics when it finds
    /// none, or two.
    fn found_in(
        region: Component,
        image: &ColorImage,
        registered: pps_schema::TagSize,
        target: &Point3<f64>,
    ) -> (TagDetection, Vec<String>) {
        let params = TagSearchParams::default().for_home_tags([registered]);
        match chosen_in(region, image, target, &params) {
            (Some(TagSighting::Found(found)), notes) => (found, notes),
            (sighting, notes) => panic!("no tag found clearly: {sighting:?} {notes:?}"),
        }
    }

    /// The plane x = 1 as `looking_along_x` sees it, 40 × 40 cm: each pixel the colour
    /// `colour_of` gives its middle, with its channels scattered by up to 8 either way.
    fn the_plane_seen(seed: u64, mut colour_of: impl FnMut(Point3<f32>) -> [u8; 3]) -> ColorImage {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let mut image = ColorImage::new(400, 400);
        for v in 0..400u32 {
            for u in 0..400u32 {
                let y = (200.0 - (f64::from(u) + 0.5)) / 1000.0;
                let z = (200.0 - (f64::from(v) + 0.5)) / 1000.0;
                let colour = colour_of(Point3::new(1.0, y as f32, z as f32));
                let i = (v as usize * 400 + u as usize) * 3;
                for (c, value) in colour.into_iter().enumerate() {
                    image.rgb[i + c] = (i16::from(value) + rng.random_range(-8i16..=8)) as u8;
                }
            }
        }
        image
    }

    #[test]
    fn a_red_things_outline_left_beside_it_does_not_join_the_tag() {
        // Pointed 4 cm into the box: its front is taken out with its colour, and what stays of
        // its outline, a ring a pixel or two wide of neither colour, touches the tag; joined,
        // the two would be far too large to be a tag, and nothing would be found.
        let (tag, red_box, image) = tag_flush_with_an_outlined_box();
        let found = found_beside_a_box(&tag, &red_box, &image);
        assert!((found.centroid - Point3::new(1.0, -0.03, 0.0)).norm() < 0.005, "{found:?}");
        assert!(found.points >= tag.len() * 9 / 10, "{} of {}", found.points, tag.len());
    }

    #[test]
    fn a_surface_that_keeps_nothing_of_the_part_is_not_cut_to() {
        // A strip 5 mm wide and 40 cm long (a tube's edge seen from its side), on the plane
        // x = 1, and a line of points 5 cm toward the robot from its middle: the opening that
        // cuts crossing strips to the band would remove the strip itself.
        let params = TagSearchParams::default();
        let target = Point3::new(1.0, 0.0, 0.0);
        let mut points: Vec<Point3<f32>> = (0..160)
            .flat_map(|j| (0..2).map(move |i| (i, j)))
            .map(|(i, j)| Point3::new(1.0, i as f32 * 0.0025, j as f32 * 0.0025 - 0.2))
            .collect();
        points.extend((1..20).map(|k| Point3::new(1.0 - k as f32 * 0.0025, 0.0, 0.0)));
        let part = region_of(&points, &target);
        assert!(on_the_nearest_surface(&part, &target, &params).is_none());
    }

    #[test]
    fn a_tag_against_a_red_box_of_its_colour_by_its_long_side_is_the_registered_rectangle() {
        // A rocker's 5.6 × 10 cm patch against the side of a red box 20 × 25 cm of its very
        // colour, flush with it, a point a pixel: colour and surface leave them one part, and
        // the disc of the tag's shape rolls over the patch too. Pointed 2 cm into the patch.
        let (found, notes) = the_patch_against_the_box(None);
        assert!((found.centroid - Point3::new(1.0, -0.028, -0.01)).norm() < 0.005, "{found:?}");
        let of_the_tag = found.members.iter().filter(|p| p.y < 0.0).count();
        assert!(of_the_tag >= 56 * 100 * 9 / 10, "{of_the_tag} of the patch's 5600 points");
        assert!(notes.iter().any(|n| n.contains("a tag's rectangle (5.6 × 10.0 cm")), "{notes:?}");
    }

    #[test]
    fn a_wood_the_search_lets_in_past_the_patchs_free_sides_is_not_the_box() {
        // The same patch and box on an orange-brown wood that passes the search's colours, a
        // band of it 3 cm wide all round: the wood is not the box's colour, so the patch's
        // three sides against it are free.
        let wood = [175, 80, 45];
        assert!(HsvThresholds::default().contains(wood), "the wood passes the thresholds");
        let (found, notes) = the_patch_against_the_box(Some(wood));
        assert!((found.centroid - Point3::new(1.0, -0.028, -0.01)).norm() < 0.005, "{found:?}");
        assert!(notes.iter().any(|n| n.contains("a tag's rectangle (5.6 × 10.0 cm")), "{notes:?}");
    }

    #[test]
    fn a_patch_of_its_own_colour_beside_a_fabric_is_taken_before_a_rectangle_in_the_fabric() {
        // A rocker's 5.8 × 8.4 cm patch against the end of a red fabric 20 × 9 cm of another
        // red, flush with it, pointed 1 cm into the fabric (rocker 59 of the corpus). The
        // colour nearest the target keeps the fabric; a rectangle of the patch's size fits in
        // the fabric's end, its top and bottom free and its side against the patch free of the
        // fabric's colour, and was taken. The patch beside it, as near the target, is the tag.
        let patch = OnThePlane { y: -0.058..0.0, z: -0.042..0.042, colour: [200, 30, 20] };
        let fabric = OnThePlane { y: 0.0..0.20, z: -0.045..0.045, colour: [170, 45, 70] };
        let registered = pps_schema::TagSize { width: 0.058, height: 0.084 };
        let target = Point3::new(1.0, 0.01, 0.0);
        let (region, image, _) = tag_and_thing(29, &patch, &fabric, &target);
        let (found, notes) = found_in(region, &image, registered, &target);
        assert!((found.centroid - Point3::new(1.0, -0.029, 0.0)).norm() < 0.005, "{notes:?}");
        let said = notes.join(" ");
        assert!(!said.contains("a tag's rectangle"), "{said}");
    }

    /// What the first step makes of a rocker's 6 × 8 cm patch on a plywood front whose
    /// orange-brown (hue 16°) the factory colour lets in, the front filling the picture, with
    /// `params` (the patch's size registered) and pointed at `target`: the parts, the patch's
    /// own points, and the notes.
    fn unmistakable_red_of_the_patch_on_wood(
        params: &TagSearchParams,
        target: &Point3<f64>,
    ) -> (Option<Vec<Component>>, Vec<Point3<f32>>, Vec<String>) {
        let patch = OnThePlane { y: -0.03..0.03, z: -0.04..0.04, colour: [200, 30, 20] };
        let wood = OnThePlane { y: -0.2..0.2, z: -0.2..0.2, colour: [175, 80, 45] };
        let (region, image, of_the_patch) = tag_and_thing(41, &patch, &wood, target);
        let calibration = looking_along_x();
        let bound = TagBound::new(params, &calibration);
        let mut notes = Vec::new();
        let parts =
            of_unmistakable_red(&region, &image, &calibration, target, params, &bound, &mut notes);
        (parts, of_the_patch, notes)
    }

    #[test]
    fn a_wood_pointed_at_beside_the_tag_is_left_for_the_tags_red() {
        // Pointed 1 cm into the wood beside the patch: the colour anchored there would be the
        // wood's, and keep the wood.
        let registered = pps_schema::TagSize { width: 0.06, height: 0.08 };
        let params = TagSearchParams::default().for_home_tags([registered]);
        let target = Point3::new(1.0, -0.04, 0.0);
        let (parts, of_the_patch, notes) = unmistakable_red_of_the_patch_on_wood(&params, &target);
        let parts = parts.expect("divided");
        let kept: Vec<&Point3<f32>> = parts.iter().flat_map(|p| &p.members).collect();
        let of_the_wood = kept.iter().filter(|p| p.y.abs() > 0.031 || p.z.abs() > 0.041).count();
        assert_eq!(of_the_wood, 0, "{notes:?}");
        // All but the patch's outermost pixels, whose colour the camera mixes with the wood's.
        assert!(kept.len() >= of_the_patch.len() * 9 / 10, "{} points {notes:?}", kept.len());
        assert_eq!(notes.len(), 1);
        assert!(notes[0].contains("outside a tag's red (340–10°)"), "{notes:?}");
    }

    #[test]
    fn a_region_pointed_at_in_the_tags_red_or_searched_in_a_learned_colour_is_left_whole() {
        let registered = pps_schema::TagSize { width: 0.06, height: 0.08 };
        let params = TagSearchParams::default().for_home_tags([registered]);
        // Pointed at the patch itself.
        let (parts, _, notes) =
            unmistakable_red_of_the_patch_on_wood(&params, &Point3::new(1.0, -0.01, 0.0));
        assert!(parts.is_none() && notes.is_empty(), "{notes:?}");
        // At the wood, by a household whose colour, learned from its towels, is 346–8°.
        let learned = TagSearchParams {
            thresholds: params.thresholds.with_hues([346.0, 8.0]),
            ..params.clone()
        };
        let (parts, _, notes) =
            unmistakable_red_of_the_patch_on_wood(&learned, &Point3::new(1.0, -0.04, 0.0));
        assert!(parts.is_none() && notes.is_empty(), "{notes:?}");
    }

    /// The tag found where a rocker's 5.6 × 10 cm patch lies against the side of a red box
    /// 20 × 25 cm of its very colour on the plane x = 1, a point a pixel, with `wood` (red
    /// enough for the search) 3 cm wide round both when given, sizes registered; and the notes.
    fn the_patch_against_the_box(wood: Option<[u8; 3]>) -> (TagDetection, Vec<String>) {
        let mut red = Vec::new();
        let image = the_plane_seen(5, |point| {
            let (y, z) = (f64::from(point.y), f64::from(point.z));
            let on_box = (0.0..0.20).contains(&y) && (-0.12..0.13).contains(&z);
            let on_tag = (-0.056..0.0).contains(&y) && (-0.06..0.04).contains(&z);
            let on_wood = (-0.086..0.23).contains(&y) && (-0.15..0.16).contains(&z);
            match wood {
                _ if on_box || on_tag => {
                    red.push(point);
                    [185, 50, 45]
                }
                Some(wood) if on_wood => {
                    red.push(point);
                    wood
                }
                _ => [120, 110, 100],
            }
        });
        let rocker = pps_schema::TagSize { width: 0.056, height: 0.10 };
        let params = TagSearchParams::default().for_home_tags([rocker]);
        let target = Point3::new(1.0, -0.02, -0.01);
        match chosen_in(region_of(&red, &target), &image, &target, &params) {
            (Some(TagSighting::Found(found)), notes) => (found, notes),
            other => panic!("the patch against the box: {other:?}"),
        }
    }
}
