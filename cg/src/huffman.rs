//! Decompression tables from data: optimal prefix codes under the format's
//! limit of 6-bit tags (package-merge), canonical tag assignment, and the
//! setTable commands that load them. The tables are Deering's modified
//! Huffman coding (M. Deering, "Geometry Compression", SIGGRAPH 1995): a
//! tag of up to 6 bits selects an entry giving the data length, a right
//! shift and absolute or relative, and setTable fills the 64 entries a tag
//! prefix covers (Java 3D API Specification, appendix B).

/// Code lengths (0..=`max_len`) minimising Σ frequency × length for
/// `freqs` (all > 0), by package-merge; one symbol gets length 0.
/// Needs `freqs.len() <= 2^max_len`.
pub(crate) fn limited_lengths(freqs: &[u64], max_len: u32) -> Vec<u32> {
    let n = freqs.len();
    if n <= 1 {
        return vec![0; n];
    }
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by_key(|&i| (freqs[i], i));
    // Items: (weight, how many times each symbol is inside).
    type Item = (u64, Vec<u8>);
    let leaves: Vec<Item> = order
        .iter()
        .map(|&i| {
            let mut c = vec![0u8; n];
            c[i] = 1;
            (freqs[i], c)
        })
        .collect();
    let mut list: Vec<Item> = leaves.clone();
    for _ in 1..max_len {
        let packages: Vec<Item> = list
            .chunks_exact(2)
            .map(|p| (p[0].0 + p[1].0, p[0].1.iter().zip(&p[1].1).map(|(a, b)| a + b).collect()))
            .collect();
        let mut merged = Vec::with_capacity(leaves.len() + packages.len());
        let (mut i, mut j) = (0, 0);
        while i < leaves.len() || j < packages.len() {
            let take_leaf = j >= packages.len() || (i < leaves.len() && leaves[i].0 <= packages[j].0);
            if take_leaf {
                merged.push(leaves[i].clone());
                i += 1;
            } else {
                merged.push(packages[j].clone());
                j += 1;
            }
        }
        list = merged;
    }
    let mut lengths = vec![0u32; n];
    for item in list.iter().take(2 * n - 2) {
        for (l, &c) in lengths.iter_mut().zip(&item.1) {
            *l += u32::from(c);
        }
    }
    lengths
}

/// Canonical tags for `lengths` (shorter first, then by symbol index).
pub(crate) fn canonical_tags(lengths: &[u32]) -> Vec<u32> {
    let mut order: Vec<usize> = (0..lengths.len()).collect();
    order.sort_by_key(|&i| (lengths[i], i));
    let mut tags = vec![0u32; lengths.len()];
    let mut code = 0u32;
    let mut prev_len = 0u32;
    for (k, &i) in order.iter().enumerate() {
        let l = lengths[i];
        if k > 0 {
            code = (code + 1) << (l - prev_len);
        }
        tags[i] = code;
        prev_len = l;
    }
    tags
}

/// One table entry to load: tag (of `tag_len` bits), data length before the
/// shift, the shift, absolute.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct TableEntry {
    pub tag: u32,
    pub tag_len: u32,
    pub data_len: u32,
    pub shift: u32,
    pub absolute: bool,
}

impl TableEntry {
    /// The setTable command for table `table` (0 position, 1 colour, 2
    /// normal): (8-bit header, 15-bit body). Data length 16 is sent as 0.
    pub(crate) fn command(&self, table: u32) -> (u32, u32) {
        let adr = (1 << self.tag_len) | self.tag;
        let header = 0x10 | (table << 1) | (adr >> 6);
        let body = ((adr & 0x3F) << 9) | ((self.data_len & 0xF) << 5) | (u32::from(self.absolute) << 4) | self.shift;
        (header, body)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn limited_lengths_respect_kraft_and_limit() {
        let freqs: Vec<u64> = (0..40u64).map(|i| 1 + i * i * i).collect();
        let l = limited_lengths(&freqs, 6);
        assert!(l.iter().all(|&x| (1..=6).contains(&x)));
        let kraft: f64 = l.iter().map(|&x| 0.5f64.powi(x as i32)).sum();
        assert!((kraft - 1.0).abs() < 1e-12, "{kraft}");
        assert_eq!(limited_lengths(&[5], 6), vec![0]);
        assert_eq!(limited_lengths(&[5, 1], 6), vec![1, 1]);
        // 64 equal symbols need exactly 6 bits each.
        assert!(limited_lengths(&[3; 64], 6).iter().all(|&x| x == 6));
    }

    #[test]
    fn canonical_tags_are_prefix_free() {
        let lengths = [2, 1, 3, 3];
        let tags = canonical_tags(&lengths);
        assert_eq!(tags, vec![0b10, 0b0, 0b110, 0b111]);
    }

    #[test]
    fn set_table_command_layout() {
        // Tag 01 (length 2) -> address 0000101; 16 bits sent as 0.
        let e = TableEntry { tag: 1, tag_len: 2, data_len: 16, shift: 0, absolute: true };
        let (h, b) = e.command(0);
        assert_eq!(h, 0x10);
        assert_eq!(b, (0b000101 << 9) | (1 << 4));
    }
}
