//! Per-vertex change stamps of [`super::Local`]: what a failed local operation needs to
//! know before it is tried again (boundary recovery, paper §4.2; the optimiser, §6).

/// Per vertex: the value of `clock` when a tet at it last changed (made, or reshaped
/// by a move). Every [`Local::replace`] stamps the vertices of the tets it makes; a
/// vertex move is stamped by its caller. A local operation that reads only the tets at
/// some vertices and is deterministic fails again while none of them has changed, so
/// callers remember a failure with the clock and retry only after a change.
#[derive(Debug, Default)]
pub(crate) struct Stamps {
    stamp: Vec<u32>,
    /// Changes so far.
    pub clock: u32,
}

impl Stamps {
    /// Records a change at the vertices `verts` (one tick of the clock).
    pub fn touch(&mut self, verts: impl IntoIterator<Item = u32>) {
        self.clock = self.clock.wrapping_add(1).max(1);
        for x in verts {
            let i = x as usize;
            if i >= self.stamp.len() {
                self.stamp.resize((i + 1).max(self.stamp.len() * 5 / 4), 0);
            }
            self.stamp[i] = self.clock;
        }
    }

    /// The stamps of `verts` (repetitions included), for [`Stamps::restore`].
    pub(super) fn read<'a>(
        &'a self,
        verts: impl IntoIterator<Item = u32> + 'a,
    ) -> impl Iterator<Item = (u32, u32)> + 'a {
        verts
            .into_iter()
            .map(|x| (x, self.stamp.get(x as usize).copied().unwrap_or(0)))
    }

    /// Puts back stamps saved by [`Stamps::read`].
    pub(super) fn restore(&mut self, saved: &[(u32, u32)]) {
        for &(x, s) in saved.iter().rev() {
            if let Some(slot) = self.stamp.get_mut(x as usize) {
                *slot = s;
            }
        }
    }

    /// The stamp of vertex `x`: the clock of the last change at it (restored by an
    /// undo), so equal stamps mean the same tets at `x`.
    pub fn of(&self, x: u32) -> u32 {
        self.stamp.get(x as usize).copied().unwrap_or(0)
    }

    /// The vertices at which a tet changed after the clock read `since`.
    pub fn touched_since(&self, since: u32) -> impl Iterator<Item = u32> + '_ {
        (0..self.stamp.len() as u32).filter(move |&x| self.stamp[x as usize] > since)
    }

    /// True when a tet at one of `verts` changed after the clock read `since`.
    pub fn changed_since(&self, verts: &[u32], since: u32) -> bool {
        verts
            .iter()
            .any(|&x| self.stamp.get(x as usize).is_some_and(|&s| s > since))
    }
}
