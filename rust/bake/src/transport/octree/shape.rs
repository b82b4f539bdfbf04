//! The octree's nodes, and its shape over an object's texels: how its nodes nest and
//! which sources each holds, found from the sources' positions and pieces
//! alone. Every gathering over the same texels, under any light (the
//! light entering, a unit light, the light raised), shares one shape and
//! only sums its own light into the nodes ([`TreeShape::lit`]): the
//! sorting that builds a tree is most of its cost, and a bake at 4096²
//! gathers over its texels half a dozen times. The sources' places in leaf
//! order are made once too ([`TreeShape::placed`]).

use crate::transport::disk_kernel::{DiskKernel, Slot};
use crate::transport::source_table::PlacedSources;
use crate::transport::sources::Sources;
use glam::{DVec3, Vec3};
use rayon::prelude::*;
use std::sync::{Arc, OnceLock};

/// Sources per leaf.
pub(super) const LEAF: usize = 8;

/// The piece of a node whose sources lie on several pieces of the mesh.
pub(super) const MIXED: u32 = u32::MAX;

#[derive(Clone, Debug, Default)]
pub(super) struct Node {
    pub(super) lo: Vec3,
    pub(super) hi: Vec3,
    /// Irradiance-weighted centre (area-weighted when unlit).
    pub(super) centre: Vec3,
    /// Area-weighted mean normal, normalised.
    pub(super) normal: Vec3,
    /// The length of the area-weighted mean of the sources' normals: 1
    /// where they all face one way, less where they turn (0 for a node of
    /// no area).
    pub(super) flatness: f32,
    pub(super) area: f32,
    /// The area of the disk whose second moment is that of the node's
    /// light about its centre, mm².
    pub(super) spread: f32,
    pub(super) slot: Slot,
    pub(super) flux: [f32; 3],
    /// Children (first, count) in `nodes`, or sources (first, count) in
    /// the table for a leaf.
    pub(super) first: u32,
    pub(super) count: u32,
    pub(super) leaf: bool,
    /// The medium every source of the node lies in, or [`MIXED`]. Nodes
    /// split by piece first, so only nodes above the pieces' own subtrees
    /// are mixed, and those are always opened.
    pub(super) piece: u32,
    /// The piece of its medium every source of the node lies on
    /// ([`Sources::part`]), or [`MIXED`]; 0 where the sources do not say.
    pub(super) part: u32,
}

/// The octree's shape over one set of sources, with the sources in its
/// leaf order.
pub struct TreeShape {
    links: Vec<Links>,
    order: Vec<u32>,
    /// The sources' places in leaf order, made with the first tree lit
    /// over the shape and shared by every later one whose disk means are
    /// sized alike (each light over the texels, each kernel).
    placed: OnceLock<Arc<PlacedSources>>,
}

/// Bytes a shape holds per texel, for the plan: its leaf order, at most
/// half a node a texel (4.75 million nodes over the head's 11.6 million
/// texels at 4096²) each with its links, and the texels' places in leaf
/// order ([`PlacedSources::BYTES_PER_SOURCE`]).
pub const BYTES_PER_TEXEL: usize =
    4 + std::mem::size_of::<Links>() / 2 + PlacedSources::BYTES_PER_SOURCE;

/// A node's place in the tree: its children (first, count) among the
/// nodes, or for a leaf its sources (first, count) in the order; and the
/// range of the order it holds.
#[derive(Clone, Copy, Debug)]
struct Links {
    first: u32,
    count: u32,
    leaf: bool,
    start: u32,
    end: u32,
}

impl TreeShape {
    /// The shape over `sources`, split at box centres (by piece first:
    /// by the piece of the mesh where a medium joins several, else by
    /// medium).
    pub fn new(sources: &Sources) -> Self {
        let mut items: Vec<Item> = (0..sources.len())
            .into_par_iter()
            .map(|i| Item {
                position: sources.position[i],
                piece: sources
                    .part
                    .get(i)
                    .or(sources.piece.get(i))
                    .copied()
                    .unwrap_or(0),
                index: i as u32,
            })
            .collect();
        let nodes = if items.is_empty() {
            Vec::new()
        } else {
            subtree(&mut items, 0, 0)
        };
        let order: Vec<u32> = items.par_iter().map(|item| item.index).collect();
        drop(items);
        let mut links: Vec<Links> = nodes
            .iter()
            .map(|n| Links {
                first: n.first,
                count: n.count,
                leaf: n.leaf,
                start: n.first,
                end: n.first + n.count,
            })
            .collect();
        // Children follow their parent, so walking back gives every node
        // the range of its children's ranges.
        for k in (0..links.len()).rev() {
            let node = links[k];
            if !node.leaf {
                links[k].start = links[node.first as usize].start;
                links[k].end = links[(node.first + node.count - 1) as usize].end;
            }
        }
        TreeShape {
            links,
            order,
            placed: OnceLock::new(),
        }
    }

    /// True when the shape was made over as many sources as `sources`
    /// holds (a shape is only ever made over the same texels).
    pub(super) fn fits(&self, sources: &Sources) -> bool {
        self.order.len() == sources.len()
    }

    /// The places in leaf order of `sources`, which lie where the shape's
    /// sources lay, with slots in `disks`: the shape's own when they were
    /// made in the same sizes, else new.
    pub(super) fn placed(&self, sources: &Sources, disks: &DiskKernel) -> Arc<PlacedSources> {
        let make = || Arc::new(PlacedSources::new(sources, &self.order, disks));
        let held = self.placed.get_or_init(make);
        if held.made_for(sources.len(), disks) {
            Arc::clone(held)
        } else {
            make()
        }
    }

    /// The nodes over `sources`, which lie where the shape's sources lay,
    /// each summing its own sources' light: the leaves from their sources,
    /// every other node from its children's summaries, so each source is
    /// read once.
    pub(super) fn lit(&self, sources: &Sources) -> Vec<Node> {
        let mut nodes: Vec<Node> = self
            .links
            .par_iter()
            .map(|links| {
                if !links.leaf {
                    return Node::default();
                }
                let (start, end) = (links.start as usize, links.end as usize);
                summarise(&self.order[start..end], sources, start)
            })
            .collect();
        // Children follow their parent: walking back, a node's children
        // are summed before it.
        for k in (0..nodes.len()).rev() {
            let links = self.links[k];
            if links.leaf {
                continue;
            }
            let (parent, after) = nodes.split_at_mut(k + 1);
            let first = links.first as usize - (k + 1);
            let node = &mut parent[k];
            *node = gathered(&after[first..first + links.count as usize]);
            (node.first, node.count, node.leaf) = (links.first, links.count, false);
        }
        nodes.par_iter_mut().for_each(|node| {
            node.flatness = (node.normal.length() / node.area).clamp(0.0, 1.0);
            node.normal = node.normal.normalize_or_zero();
        });
        nodes
    }
}

/// The node over `children` (which split its sources between them) from
/// their summaries alone: areas, fluxes and area-weighted normals add; the
/// centre is the children's centres weighed by their light (by their area
/// where none is lit, as [`summarise`] weighs sources), and the second
/// moment about it each child's own plus its centre's offset squared (the
/// parallel-axis theorem), so no large squares cancel.
fn gathered(children: &[Node]) -> Node {
    let light_of = |n: &Node| {
        let [r, g, b] = n.flux.map(f64::from);
        (0.2126 * r + 0.7152 * g + 0.0722 * b).max(0.0)
    };
    let lit = children.iter().any(|n| light_of(n) > 0.0);
    let weight = |n: &Node| {
        if lit {
            light_of(n)
        } else {
            f64::from(n.area.max(0.0))
        }
    };
    let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
    let (mut area, mut flux, mut normal) = (0.0f64, [0.0f64; 3], Vec3::ZERO);
    let (mut total, mut by_weight) = (0.0f64, DVec3::ZERO);
    for n in children {
        lo = lo.min(n.lo);
        hi = hi.max(n.hi);
        area += f64::from(n.area);
        for (sum, &f) in flux.iter_mut().zip(&n.flux) {
            *sum += f64::from(f);
        }
        normal += n.normal;
        total += weight(n);
        by_weight += n.centre.as_dvec3() * weight(n);
    }
    let (centre, second_moment) = if total > 0.0 {
        let c = by_weight / total;
        let moment: f64 = children
            .iter()
            .map(|n| {
                let own = f64::from(n.spread) / std::f64::consts::TAU;
                weight(n) * (own + (n.centre.as_dvec3() - c).length_squared())
            })
            .sum();
        (c, moment / total)
    } else {
        (0.5 * (lo + hi).as_dvec3(), 0.0)
    };
    let one = |of: fn(&Node) -> u32| match children.first().map(of) {
        Some(first) if children.iter().all(|n| of(n) == first) => first,
        Some(_) => MIXED,
        None => 0,
    };
    let (piece, part) = (one(|n| n.piece), one(|n| n.part));
    let mut node = summary(
        Bounds { lo, hi, piece },
        centre,
        normal,
        area,
        second_moment,
        flux,
    );
    node.part = part;
    node
}

/// A node's box and the piece its sources lie on ([`MIXED`] for several):
/// their medium once lit, the piece they are split by while built.
struct Bounds {
    lo: Vec3,
    hi: Vec3,
    piece: u32,
}

/// The node of `bounds` whose sources' light centres at `centre` with
/// `second_moment` about it (mm²), of `area` (mm²) and `flux` per channel,
/// and with the area-weighted sum `normal` of their normals (normalised
/// once the tree is lit, [`TreeShape::lit`]: a parent adds its
/// children's): not yet placed among the nodes.
fn summary(
    bounds: Bounds,
    centre: DVec3,
    normal: Vec3,
    area: f64,
    second_moment: f64,
    flux: [f64; 3],
) -> Node {
    Node {
        lo: bounds.lo,
        hi: bounds.hi,
        centre: centre.as_vec3(),
        normal,
        flatness: 0.0,
        area: area as f32,
        // A disk of radius a has second moment a²/2 about its centre.
        spread: (std::f64::consts::TAU * second_moment.max(0.0)) as f32,
        slot: Slot::default(),
        flux: flux.map(|f| f as f32),
        first: 0,
        count: 0,
        leaf: false,
        piece: bounds.piece,
        part: 0,
    }
}

/// Levels below the root whose subtrees are built in parallel.
const PARALLEL_LEVELS: u32 = 3;
/// The fewest sources a subtree is built in parallel for.
const PARALLEL_SOURCES: usize = 50_000;

/// A source as the shape is built from it: its place and piece (of the
/// mesh where media join several, else its medium) beside its index, so
/// the splits at every level read the items in order rather than the
/// sources at random.
#[derive(Clone, Copy)]
struct Item {
    position: Vec3,
    piece: u32,
    index: u32,
}

/// A node as the shape is built: its children (first, count) among the
/// nodes, or for a leaf its items (first, count) in the order.
#[derive(Clone, Copy, Default)]
struct Built {
    first: u32,
    count: u32,
    leaf: bool,
}

/// Fills node `at` of `nodes` from `items` (a slice of the order starting
/// at `offset`), splitting at the box centre, its children after every
/// node before them.
fn build(nodes: &mut Vec<Built>, at: usize, items: &mut [Item], offset: usize) {
    nodes[at] = leaf(items, offset);
    let Some(children) = split(&mut nodes[at], items) else {
        return;
    };
    let first_child = nodes.len();
    nodes[at].first = first_child as u32;
    nodes.resize(first_child + children.len(), Built::default());
    for (k, (a, b)) in children.into_iter().enumerate() {
        build(nodes, first_child + k, &mut items[a..b], offset + a);
    }
}

/// The nodes of the subtree over `items` (a slice of the order starting at
/// `offset`, `depth` levels below the root), its root first and each
/// node's children contiguous: the top levels' subtrees built in parallel,
/// each a block laid out as [`build`] lays out a whole tree.
fn subtree(items: &mut [Item], offset: usize, depth: u32) -> Vec<Built> {
    if depth >= PARALLEL_LEVELS || items.len() < PARALLEL_SOURCES {
        let mut nodes = vec![Built::default()];
        build(&mut nodes, 0, items, offset);
        return nodes;
    }
    let mut root = leaf(items, offset);
    let Some(children) = split(&mut root, items) else {
        return vec![root];
    };
    let mut slices = Vec::with_capacity(children.len());
    let mut rest = items;
    for &(a, b) in &children {
        let (head, tail) = rest.split_at_mut(b - a);
        slices.push((head, offset + a));
        rest = tail;
    }
    let blocks: Vec<Vec<Built>> = slices
        .into_par_iter()
        .map(|(slice, at)| subtree(slice, at, depth + 1))
        .collect();
    // The children's roots follow the root; each block's other nodes
    // follow them in turn, every index into a block shifted alike.
    let count = blocks.len();
    root.first = 1;
    let mut nodes = Vec::with_capacity(1 + blocks.iter().map(Vec::len).sum::<usize>());
    nodes.push(root);
    nodes.extend(std::iter::repeat_n(Built::default(), count));
    for (k, block) in blocks.into_iter().enumerate() {
        let shift = (nodes.len() - 1) as u32;
        let shifted = |mut node: Built| {
            if !node.leaf {
                node.first += shift;
            }
            node
        };
        let mut block = block.into_iter();
        if let Some(child) = block.next() {
            nodes[1 + k] = shifted(child);
        }
        nodes.extend(block.map(shifted));
    }
    nodes
}

/// The leaf over `items` (a slice of the order starting at `offset`),
/// until split.
fn leaf(items: &[Item], offset: usize) -> Built {
    Built {
        first: offset as u32,
        count: items.len() as u32,
        leaf: true,
    }
}

/// The node over the sources in `items` (a slice of the order starting
/// at `offset`), a leaf until split.
fn summarise(items: &[u32], sources: &Sources, offset: usize) -> Node {
    let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
    let mut area = 0.0f64;
    let mut flux = [0.0f64; 3];
    // Light- and area-weighted sums of position, |position|² and each
    // texel's own second moment A/2π (a disk's).
    let (mut light, mut by_light, mut square_by_light) = (0.0f64, DVec3::ZERO, 0.0f64);
    let (mut by_area, mut square_by_area) = (DVec3::ZERO, 0.0f64);
    let mut normal = Vec3::ZERO;
    let one = |of: &[u32]| {
        let of = |i: &u32| of.get(*i as usize).copied().unwrap_or(0);
        match items.first().map(of) {
            Some(first) if items.iter().all(|i| of(i) == first) => first,
            Some(_) => MIXED,
            None => 0,
        }
    };
    let (piece, part) = (one(&sources.piece), one(&sources.part));
    for &i in items.iter() {
        let i = i as usize;
        let p = sources.position[i];
        lo = lo.min(p);
        hi = hi.max(p);
        let a = sources.area[i].max(0.0) as f64;
        let e = sources.irradiance[i];
        area += a;
        for c in 0..3 {
            flux[c] += e[c] as f64 * a;
        }
        let q = p.as_dvec3();
        let own = a / std::f64::consts::TAU;
        let l = (0.2126 * e[0] + 0.7152 * e[1] + 0.0722 * e[2]).max(0.0) as f64 * a;
        light += l;
        by_light += q * l;
        square_by_light += (q.length_squared() + own) * l;
        by_area += q * a;
        square_by_area += (q.length_squared() + own) * a;
        normal += sources.normal[i] * a as f32;
    }
    let (centre, second_moment) = if light > 0.0 {
        let c = by_light / light;
        (c, square_by_light / light - c.length_squared())
    } else if area > 0.0 {
        let c = by_area / area;
        (c, square_by_area / area - c.length_squared())
    } else {
        (0.5 * (lo + hi).as_dvec3(), 0.0)
    };
    let bounds = Bounds { lo, hi, piece };
    Node {
        first: offset as u32,
        count: items.len() as u32,
        leaf: true,
        part,
        ..summary(bounds, centre, normal, area, second_moment, flux)
    }
}

/// Sorts `items` into `node`'s children and makes it their parent: the
/// children's ranges in `items`, or `None` for a leaf.
fn split(node: &mut Built, items: &mut [Item]) -> Option<Vec<(usize, usize)>> {
    let Bounds { lo, hi, piece } = bounds(items);
    let mixed = piece == MIXED;
    if !mixed && (items.len() <= LEAF || (hi - lo).max_element() <= 0.0) {
        return None;
    }
    // Sources of several pieces are split by piece, the rest at the
    // box centre.
    let mid = 0.5 * (lo + hi);
    let child_of = |item: &Item| -> u32 {
        if mixed {
            return item.piece;
        }
        let p = item.position;
        (p.x > mid.x) as u32 | ((p.y > mid.y) as u32) << 1 | ((p.z > mid.z) as u32) << 2
    };
    items.sort_unstable_by_key(child_of);
    let mut children: Vec<(usize, usize)> = Vec::with_capacity(8);
    let mut start = 0;
    for k in 1..=items.len() {
        if k == items.len() || child_of(&items[k]) != child_of(&items[start]) {
            children.push((start, k));
            start = k;
        }
    }
    node.count = children.len() as u32;
    node.leaf = false;
    Some(children)
}

/// The box of `items` and the piece they lie on ([`MIXED`] for several).
fn bounds(items: &[Item]) -> Bounds {
    let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
    for item in items {
        lo = lo.min(item.position);
        hi = hi.max(item.position);
    }
    let piece = match items.first() {
        Some(first) if items.iter().all(|i| i.piece == first.piece) => first.piece,
        Some(_) => MIXED,
        None => 0,
    };
    Bounds { lo, hi, piece }
}

#[cfg(test)]
mod tests {
    use super::*;
    use sssbake_profile::numerics::rng::Rng;
    use std::borrow::Cow;

    /// Sources on two pieces of a bent sheet, some unlit, under a light.
    fn sources(light: impl Fn(usize) -> [f32; 3]) -> Sources<'static> {
        let mut rng = Rng::new(11, 0);
        // More than PARALLEL_SOURCES: the top levels are built in parallel.
        let n = 60_000;
        let position: Vec<Vec3> = (0..n)
            .map(|_| {
                let (u, v) = (rng.uniform() as f32 * 40.0, rng.uniform() as f32 * 40.0);
                Vec3::new(u, v, 0.02 * (u - 20.0) * (u - 20.0))
            })
            .collect();
        let normal = position
            .iter()
            .map(|p| Vec3::new(-0.04 * (p.x - 20.0), 0.0, 1.0).normalize())
            .collect();
        Sources {
            piece: Cow::Owned(position.iter().map(|p| u32::from(p.y > 30.0)).collect()),
            part: Default::default(),
            position: Cow::Owned(position),
            normal: Cow::Owned(normal),
            area: Cow::Owned((0..n).map(|i| 0.05 + 0.01 * (i % 7) as f32).collect()),
            irradiance: (0..n).map(light).collect(),
            footprint: Cow::Owned(Vec::new()),
        }
    }

    /// A shape made under one light and lit under another sums each node
    /// as a tree built under the other light from its sources does: its
    /// centre, spread, flux, area, normal, box and piece.
    #[test]
    fn a_shape_lit_anew_sums_each_node_as_its_own_sources_do() {
        let shape = TreeShape::new(&sources(|_| [1.0; 3]));
        let light = |i: usize| {
            let on = f32::from(u8::from(!i.is_multiple_of(5)));
            [on * (i % 13) as f32, on * 0.3, 0.0]
        };
        let sources = sources(light);
        let n = sources.len();
        let lit = shape.lit(&sources);
        assert!(n > PARALLEL_SOURCES && lit.len() > 1000, "{}", lit.len());
        let close = |a: f32, b: f32, scale: f32| (a - b).abs() <= 1e-4 * scale.max(1e-6);
        for (links, node) in shape.links.iter().zip(&lit) {
            let (start, end) = (links.start as usize, links.end as usize);
            let own = summarise(&shape.order[start..end], &sources, start);
            let size = (own.hi - own.lo).max_element().max(1.0);
            assert_eq!((node.lo, node.hi, node.piece), (own.lo, own.hi, own.piece));
            assert!(close(node.area, own.area, own.area));
            for c in 0..3 {
                assert!(close(
                    node.flux[c],
                    own.flux[c],
                    own.flux[0].max(own.flux[1])
                ));
            }
            assert!(close(node.centre.distance(own.centre), 0.0, size));
            assert!(close(
                node.spread,
                own.spread,
                own.spread.max(size * size * 1e-3)
            ));
            assert!(node.normal.distance(own.normal.normalize_or_zero()) < 1e-4);
            assert_eq!(
                (node.first, node.count, node.leaf),
                (links.first, links.count, links.leaf)
            );
        }
        // The pieces split first, so the root holds both and is opened.
        assert_eq!(lit[0].piece, MIXED);
    }
}
