//! Connected components by flood fill, over any graph given by its neighbours: the 3D voxels
//! of the red points (26-connected) and the 2D cells of a plane's points (8-connected) are
//! labelled by the one routine.

/// What a flood fill found: each node's component, and each component's nodes.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Components {
    /// The component of each node, `None` for nodes that are not occupied.
    pub label: Vec<Option<u32>>,
    /// The nodes of each component, in the order the fill reached them; components are
    /// numbered in the order of their lowest node.
    pub members: Vec<Vec<usize>>,
}

/// Labels the occupied nodes among `0..nodes`, joining each with the occupied nodes
/// `neighbours(node, push)` pushes.
pub fn flood_fill(
    nodes: usize,
    occupied: impl Fn(usize) -> bool,
    mut neighbours: impl FnMut(usize, &mut dyn FnMut(usize)),
) -> Components {
    let mut label: Vec<Option<u32>> = vec![None; nodes];
    let mut members = Vec::new();
    let mut stack = Vec::new();
    for seed in 0..nodes {
        if label[seed].is_some() || !occupied(seed) {
            continue;
        }
        let id = members.len() as u32;
        label[seed] = Some(id);
        stack.push(seed);
        let mut reached = Vec::new();
        while let Some(node) = stack.pop() {
            reached.push(node);
            neighbours(node, &mut |n| {
                if label[n].is_none() && occupied(n) {
                    label[n] = Some(id);
                    stack.push(n);
                }
            });
        }
        members.push(reached);
    }
    Components { label, members }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_path_and_an_island_are_two_components() {
        // 0 - 1 - 2   3 (unoccupied)   4
        let occupied = |n: usize| n != 3;
        let found = flood_fill(5, occupied, |n, push| {
            if n > 0 {
                push(n - 1);
            }
            if n < 4 {
                push(n + 1);
            }
        });
        assert_eq!(found.label, [Some(0), Some(0), Some(0), None, Some(1)]);
        let mut first = found.members[0].clone();
        first.sort_unstable();
        assert_eq!(first, [0, 1, 2]);
        assert_eq!(found.members[1], [4]);
    }
}
