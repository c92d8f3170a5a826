//! Disjoint sets (union-find with path halving): which items end up joined.

pub struct Sets {
    parent: Vec<usize>,
}

impl Sets {
    /// `n` items, each on its own.
    pub fn new(n: usize) -> Self {
        Self {
            parent: (0..n).collect(),
        }
    }

    /// The representative of `i`'s set.
    pub fn find(&mut self, mut i: usize) -> usize {
        while self.parent[i] != i {
            self.parent[i] = self.parent[self.parent[i]];
            i = self.parent[i];
        }
        i
    }

    /// Joins the sets of `a` and `b`.
    pub fn join(&mut self, a: usize, b: usize) {
        let (ra, rb) = (self.find(a), self.find(b));
        self.parent[ra] = rb;
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn joined_items_share_a_representative() {
        let mut s = super::Sets::new(5);
        s.join(0, 3);
        s.join(3, 4);
        assert_eq!(s.find(0), s.find(4));
        assert_ne!(s.find(1), s.find(0));
        assert_ne!(s.find(1), s.find(2));
    }
}
