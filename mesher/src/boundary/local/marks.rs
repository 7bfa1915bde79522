//! Membership sets of the local operations (boundary recovery, paper §4.2).

/// Membership marks over ids (tet slots, vertices) with an epoch, so that emptying
/// them costs nothing: for the sets a local operation builds many times.
#[derive(Debug, Default)]
pub(crate) struct Marks {
    mark: Vec<u32>,
    epoch: u32,
}

impl Marks {
    /// Empties the marks, for ids below `n`.
    pub fn clear(&mut self, n: usize) {
        if self.mark.len() < n {
            self.mark.resize(n, 0);
        }
        self.epoch = self.epoch.wrapping_add(1);
        if self.epoch == 0 {
            self.mark.fill(0);
            self.epoch = 1;
        }
    }

    /// Marks `i`; true when it was not marked.
    pub fn insert(&mut self, i: u32) -> bool {
        let m = &mut self.mark[i as usize];
        let fresh = *m != self.epoch;
        *m = self.epoch;
        fresh
    }

    /// Whether `i` is marked.
    pub fn contains(&self, i: u32) -> bool {
        self.mark.get(i as usize) == Some(&self.epoch)
    }
}
