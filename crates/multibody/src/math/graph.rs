//! Graph algorithms for sorting equations: a maximum matching of
//! equations to the unknowns they mention, and the strongly connected
//! components of a dependency graph in topological order (Tarjan).

/// A maximum matching of rows (equations) to columns (unknowns), where
/// `adjacency[r]` lists the columns row `r` may be matched to. Returns
/// the column of each row and the row of each column (`usize::MAX` where
/// unmatched). Augmenting paths from a greedy start: `O(rows * edges)` at
/// worst, near-linear on the sparse systems models make.
pub fn maximum_matching(adjacency: &[Vec<usize>], columns: usize) -> (Vec<usize>, Vec<usize>) {
    let rows = adjacency.len();
    let mut col_of = vec![usize::MAX; rows];
    let mut row_of = vec![usize::MAX; columns];
    // Greedy: rows with fewer choices first get their first free column.
    let mut order: Vec<usize> = (0..rows).collect();
    order.sort_by_key(|&r| adjacency[r].len());
    for &r in &order {
        if let Some(&c) = adjacency[r].iter().find(|&&c| row_of[c] == usize::MAX) {
            col_of[r] = c;
            row_of[c] = r;
        }
    }
    let mut visited = vec![usize::MAX; columns];
    // Explicit stack of (row, next adjacency index) for the depth-first search.
    let mut stack: Vec<(usize, usize)> = Vec::new();
    for (round, &start) in order.iter().enumerate() {
        if col_of[start] != usize::MAX {
            continue;
        }
        stack.clear();
        stack.push((start, 0));
        let mut found = None;
        'search: while let Some(&mut (r, ref mut next)) = stack.last_mut() {
            while *next < adjacency[r].len() {
                let c = adjacency[r][*next];
                *next += 1;
                if visited[c] == round {
                    continue;
                }
                visited[c] = round;
                if row_of[c] == usize::MAX {
                    found = Some(c);
                    break 'search;
                }
                stack.push((row_of[c], 0));
                continue 'search;
            }
            stack.pop();
        }
        if let Some(mut c) = found {
            // Flip the path: each row on the stack takes the column it reached.
            while let Some((r, next)) = stack.pop() {
                let reached = adjacency[r][next - 1];
                debug_assert!(reached == c);
                let previous = col_of[r];
                col_of[r] = c;
                row_of[c] = r;
                c = previous;
            }
        }
    }
    (col_of, row_of)
}

/// The strongly connected components of the graph whose node `n` depends
/// on the nodes `edges[n]`, each component after every component it
/// depends on (Tarjan's algorithm, iterative).
pub fn strongly_connected_components(edges: &[Vec<usize>]) -> Vec<Vec<usize>> {
    let n = edges.len();
    let mut index = vec![usize::MAX; n];
    let mut low = vec![0; n];
    let mut on_stack = vec![false; n];
    let mut stack = Vec::new();
    let mut components = Vec::new();
    let mut counter = 0;
    let mut call: Vec<(usize, usize)> = Vec::new();
    for root in 0..n {
        if index[root] != usize::MAX {
            continue;
        }
        call.push((root, 0));
        index[root] = counter;
        low[root] = counter;
        counter += 1;
        stack.push(root);
        on_stack[root] = true;
        while let Some(&mut (v, ref mut next)) = call.last_mut() {
            if *next < edges[v].len() {
                let w = edges[v][*next];
                *next += 1;
                if index[w] == usize::MAX {
                    index[w] = counter;
                    low[w] = counter;
                    counter += 1;
                    stack.push(w);
                    on_stack[w] = true;
                    call.push((w, 0));
                } else if on_stack[w] {
                    low[v] = low[v].min(index[w]);
                }
                continue;
            }
            call.pop();
            if let Some(&(parent, _)) = call.last() {
                low[parent] = low[parent].min(low[v]);
            }
            if low[v] == index[v] {
                let mut component = Vec::new();
                while let Some(w) = stack.pop() {
                    on_stack[w] = false;
                    component.push(w);
                    if w == v {
                        break;
                    }
                }
                component.reverse();
                components.push(component);
            }
        }
    }
    components
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matching_needs_augmenting_paths() {
        // Greedy gives row 1 column 0 and leaves row 0 without; the path fixes it.
        let adjacency = vec![vec![0], vec![0, 1], vec![1, 2]];
        let (col_of, row_of) = maximum_matching(&adjacency, 3);
        assert!(col_of.iter().all(|&c| c != usize::MAX));
        for (r, &c) in col_of.iter().enumerate() {
            assert_eq!(row_of[c], r);
            assert!(adjacency[r].contains(&c));
        }
        // Two rows that can only take one column: one stays unmatched.
        let (col_of, _) = maximum_matching(&[vec![0], vec![0]], 1);
        assert_eq!(col_of.iter().filter(|&&c| c == usize::MAX).count(), 1);
    }

    #[test]
    fn components_come_after_what_they_depend_on() {
        // 0 -> 1 <-> 2 -> 3, and 4 alone.
        let edges = vec![vec![1], vec![2], vec![1, 3], vec![], vec![]];
        let components = strongly_connected_components(&edges);
        let position = |n: usize| components.iter().position(|c| c.contains(&n)).unwrap();
        assert_eq!(components.len(), 4);
        assert_eq!(position(1), position(2));
        assert!(position(3) < position(1) && position(1) < position(0));
    }
}
