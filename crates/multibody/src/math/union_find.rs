//! Disjoint sets, for merging connectors into nodes and nodes into links.

pub struct UnionFind {
    parent: Vec<usize>,
}

impl UnionFind {
    pub fn new(n: usize) -> Self {
        Self { parent: (0..n).collect() }
    }

    pub fn find(&mut self, mut x: usize) -> usize {
        while self.parent[x] != x {
            self.parent[x] = self.parent[self.parent[x]];
            x = self.parent[x];
        }
        x
    }

    pub fn union(&mut self, a: usize, b: usize) {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra != rb {
            // Keep the smaller index as the root so that classes are stable.
            let (lo, hi) = if ra < rb { (ra, rb) } else { (rb, ra) };
            self.parent[hi] = lo;
        }
    }

    /// Class of each element, numbered 0.. in order of first appearance.
    pub fn classes(&mut self) -> (Vec<usize>, usize) {
        let n = self.parent.len();
        let mut number = vec![usize::MAX; n];
        let mut class = vec![0; n];
        let mut count = 0;
        for (x, class_of_x) in class.iter_mut().enumerate() {
            let r = self.find(x);
            if number[r] == usize::MAX {
                number[r] = count;
                count += 1;
            }
            *class_of_x = number[r];
        }
        (class, count)
    }
}
