//! The implicit model's Hessian: where its entries go, and its factor.
//!
//! The first assembly lists the entries as
//! triplets and builds the lower triangle's pattern from them; the pattern is fixed by
//! the topology and the entries come in the same order every time, so each later
//! assembly adds every entry straight into its place in the matrix's values (sorting
//! the triplets each time was 60% of a drape test, gathering them through a
//! permutation 16%).

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::sparse::linalg::cholesky::{
    SymbolicCholesky, SymmetricOrdering, factorize_symbolic_cholesky,
};
use faer::sparse::{Pair, SparseColMatRef, SymbolicSparseColMat, Triplet};
use faer::{Conj, MatMut, Par, Side};

use super::ImplicitError;

fn fail(e: &dyn std::fmt::Debug) -> ImplicitError {
    ImplicitError::Factorisation(format!("{e:?}"))
}

/// The Cholesky factor of the Hessian, its symbolic part computed once, its values and
/// scratch kept from one factorisation to the next.
pub(super) struct Factor {
    symbolic: SymbolicCholesky<usize>,
    values: Vec<f64>,
    scratch: MemBuffer,
}

impl Factor {
    pub(super) fn new(a: SparseColMatRef<'_, usize, f64>) -> Result<Self, ImplicitError> {
        let symbolic = factorize_symbolic_cholesky(
            a.symbolic(),
            Side::Lower,
            SymmetricOrdering::Amd,
            Default::default(),
        )
        .map_err(|e| fail(&e))?;
        let need = symbolic
            .factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default())
            .or(symbolic.solve_in_place_scratch::<f64>(1, Par::Seq));
        Ok(Self {
            values: vec![0.0; symbolic.len_val()],
            scratch: MemBuffer::try_new(need).map_err(|e| fail(&e))?,
            symbolic,
        })
    }

    /// Factors `a` (its pattern the one this factor was made for) and solves `a x = rhs`
    /// in place; fails when `a` is not positive definite.
    pub(super) fn solve(
        &mut self,
        a: SparseColMatRef<'_, usize, f64>,
        rhs: MatMut<'_, f64>,
    ) -> Result<(), ImplicitError> {
        let llt = self
            .symbolic
            .factorize_numeric_llt(
                &mut self.values,
                a,
                Side::Lower,
                LltRegularization::default(),
                Par::Seq,
                MemStack::new(&mut self.scratch),
                Default::default(),
            )
            .map_err(|e| fail(&e))?;
        llt.solve_in_place_with_conj(Conj::No, rhs, Par::Seq, MemStack::new(&mut self.scratch));
        Ok(())
    }
}

#[derive(Default)]
pub(super) struct Entries {
    /// The pattern, and each entry's place in the values, in the order they come.
    pattern: Option<(SymbolicSparseColMat<usize>, Vec<u32>)>,
    /// The first assembly's entries.
    triplets: Vec<Triplet<usize, usize, f64>>,
    values: Vec<f64>,
    /// Entries added in this assembly.
    next: usize,
}

impl Entries {
    /// Starts an assembly.
    pub(super) fn begin(&mut self) {
        self.next = 0;
        self.triplets.clear();
        self.values.iter_mut().for_each(|v| *v = 0.0);
    }

    /// Adds `val` at (`row`, `col`), `row >= col`.
    #[inline]
    pub(super) fn add(&mut self, row: usize, col: usize, val: f64) {
        match &self.pattern {
            Some((_, place)) => {
                if let Some(&k) = place.get(self.next) {
                    self.values[k as usize] += val;
                }
            }
            None => self.triplets.push(Triplet::new(row, col, val)),
        }
        self.next += 1;
    }

    /// The assembled lower triangle, `dim` x `dim`.
    pub(super) fn matrix(
        &mut self,
        dim: usize,
    ) -> Result<SparseColMatRef<'_, usize, f64>, ImplicitError> {
        if self.pattern.is_none() {
            self.build(dim)?;
        }
        let Some((symbolic, place)) = &self.pattern else {
            return Err(ImplicitError::Factorisation("no pattern".into()));
        };
        if self.next != place.len() {
            return Err(ImplicitError::Factorisation(format!(
                "the Hessian had {} entries, its pattern {}",
                self.next,
                place.len()
            )));
        }
        Ok(SparseColMatRef::new(symbolic.as_ref(), &self.values))
    }

    /// The pattern and each entry's place from the first assembly's triplets, and their
    /// values summed into it.
    fn build(&mut self, dim: usize) -> Result<(), ImplicitError> {
        let pairs: Vec<Pair<usize, usize>> = self
            .triplets
            .iter()
            .map(|t| Pair {
                row: t.row,
                col: t.col,
            })
            .collect();
        let (symbolic, _) =
            SymbolicSparseColMat::try_new_from_indices(dim, dim, &pairs).map_err(|e| fail(&e))?;
        let (col_ptr, row_idx) = (symbolic.col_ptr(), symbolic.row_idx());
        let mut place = Vec::with_capacity(self.triplets.len());
        self.values = vec![0.0; row_idx.len()];
        for t in &self.triplets {
            let (start, end) = (col_ptr[t.col], col_ptr[t.col + 1]);
            let k = start
                + row_idx[start..end]
                    .binary_search(&t.row)
                    .map_err(|_| fail(&"an entry outside its own pattern"))?;
            place.push(u32::try_from(k).map_err(|e| fail(&e))?);
            self.values[k] += t.val;
        }
        self.triplets = Vec::new();
        self.pattern = Some((symbolic, place));
        Ok(())
    }

    /// The first assembly's entries (tests compare the matrix with them).
    #[cfg(test)]
    pub(super) fn triplets(&self) -> &[Triplet<usize, usize, f64>] {
        &self.triplets
    }
}
