//! Channel naming (spec §3): view `v` of colour `C` is the EXR channel
//! `v{v}.{C}` with `v` zero-padded to at least three digits, the same width for
//! every view, so that EXR's alphabetical channel order is (view, colour).

use crate::geometry::Geometry;

/// Digits used for view indices in channel names.
pub fn view_digits(view_count: usize) -> usize {
    let mut digits = 1;
    let mut n = view_count.saturating_sub(1);
    while n >= 10 {
        n /= 10;
        digits += 1;
    }
    digits.max(3)
}

/// The channel name of view `v`, colour `colour`.
pub fn channel_name(v: usize, colour: &str, digits: usize) -> String {
    format!("v{v:0digits$}.{colour}")
}

/// The channels of each part of a full-parallax file (spec §8): the colour
/// suffixes alone, in EXR's (ASCII) order.
pub fn colour_names(g: &Geometry) -> Vec<String> {
    let mut names: Vec<String> = g.channels.iter().map(|c| c.name.clone()).collect();
    names.sort();
    names
}

/// For each channel of a full-parallax part, in list order, the geometry's
/// colour index (spec §8: the channels are the colours, in ASCII order).
pub(crate) fn colour_slots(g: &Geometry) -> Vec<usize> {
    colour_names(g).iter().filter_map(|n| g.channel_index(n)).collect()
}

/// Parse `v<digits>.<colour>` into (view, colour, digit count).
pub fn parse_channel_name(name: &str) -> Option<(usize, &str, usize)> {
    let rest = name.strip_prefix('v')?;
    let (digits, colour) = rest.split_once('.')?;
    if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) || digits.len() > 6 {
        return None;
    }
    Some((digits.parse().ok()?, colour, digits.len()))
}

/// The EXR channel list order of a geometry's (view, colour) pairs.
///
/// EXR sorts channels by name; with equal-width view numbers that is view
/// major, and within a view the colour suffixes in ASCII order (B, G, R, Y).
#[derive(Clone, Debug)]
pub struct ChannelOrder {
    /// `slot[v * colours + c]` = position of (view v, colour c) in the channel list.
    slot: Vec<usize>,
    /// `pair[slot]` = (view, colour index) of the channel at that position.
    pair: Vec<(usize, usize)>,
    colours: usize,
}

impl ChannelOrder {
    /// The order for a geometry.
    pub fn new(g: &Geometry) -> Self {
        let colours = g.channels.len();
        let digits = view_digits(g.views.count);
        let mut named: Vec<(String, usize, usize)> = (0..g.views.count)
            .flat_map(|v| g.channels.iter().enumerate().map(move |(c, ch)| (channel_name(v, &ch.name, digits), v, c)))
            .collect();
        named.sort();
        let mut slot = vec![0; named.len()];
        let pair: Vec<(usize, usize)> = named.iter().map(|(_, v, c)| (*v, *c)).collect();
        for (s, (v, c)) in pair.iter().enumerate() {
            slot[v * colours + c] = s;
        }
        ChannelOrder { slot, pair, colours }
    }
    /// Number of channels.
    pub fn len(&self) -> usize {
        self.pair.len()
    }
    /// Whether there are no channels.
    pub fn is_empty(&self) -> bool {
        self.pair.is_empty()
    }
    /// List position of (view, colour index).
    #[inline]
    pub fn slot_of(&self, view: usize, colour: usize) -> usize {
        self.slot[view * self.colours + colour]
    }
    /// (view, colour index) at a list position.
    #[inline]
    pub fn pair_at(&self, slot: usize) -> (usize, usize) {
        self.pair[slot]
    }
    /// Sorted channel names.
    pub fn names(&self, g: &Geometry) -> Vec<String> {
        let digits = view_digits(g.views.count);
        self.pair.iter().map(|(v, c)| channel_name(*v, &g.channels[*c].name, digits)).collect()
    }
}
