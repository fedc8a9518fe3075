//! Spatial (6-D) vector algebra in Featherstone's notation, angular part
//! first, with every quantity stored as 3-D blocks so that nothing in the
//! dynamics multiplies dense 6x6 matrices.

use super::{Mat3, Vec3};
use std::ops::{Add, AddAssign, Mul, Neg, Sub, SubAssign};

/// A spatial motion vector: angular velocity (or acceleration) `ang` and the
/// linear velocity `lin` of the point at the frame origin.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Motion {
    pub ang: Vec3,
    pub lin: Vec3,
}

/// A spatial force vector: moment `ang` about the frame origin and force `lin`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Force {
    pub ang: Vec3,
    pub lin: Vec3,
}

macro_rules! vector_ops {
    ($t:ident) => {
        impl $t {
            pub const ZERO: $t = $t { ang: Vec3::new(0.0, 0.0, 0.0), lin: Vec3::new(0.0, 0.0, 0.0) };
            #[inline]
            pub fn new(ang: Vec3, lin: Vec3) -> Self {
                Self { ang, lin }
            }
        }
        impl Add for $t {
            type Output = $t;
            #[inline]
            fn add(self, o: $t) -> $t {
                $t { ang: self.ang + o.ang, lin: self.lin + o.lin }
            }
        }
        impl Sub for $t {
            type Output = $t;
            #[inline]
            fn sub(self, o: $t) -> $t {
                $t { ang: self.ang - o.ang, lin: self.lin - o.lin }
            }
        }
        impl AddAssign for $t {
            #[inline]
            fn add_assign(&mut self, o: $t) {
                self.ang += o.ang;
                self.lin += o.lin;
            }
        }
        impl SubAssign for $t {
            #[inline]
            fn sub_assign(&mut self, o: $t) {
                self.ang -= o.ang;
                self.lin -= o.lin;
            }
        }
        impl Mul<f64> for $t {
            type Output = $t;
            #[inline]
            fn mul(self, s: f64) -> $t {
                $t { ang: self.ang * s, lin: self.lin * s }
            }
        }
        impl Neg for $t {
            type Output = $t;
            #[inline]
            fn neg(self) -> $t {
                $t { ang: -self.ang, lin: -self.lin }
            }
        }
    };
}
vector_ops!(Motion);
vector_ops!(Force);

impl Motion {
    /// `self x m`: the motion cross product (derivative of a motion vector
    /// carried by a frame moving at `self`).
    #[inline]
    pub fn cross_motion(&self, m: &Motion) -> Motion {
        Motion { ang: self.ang.cross(&m.ang), lin: self.ang.cross(&m.lin) + self.lin.cross(&m.ang) }
    }

    /// `self x* f`: the force cross product.
    #[inline]
    pub fn cross_force(&self, f: &Force) -> Force {
        Force { ang: self.ang.cross(&f.ang) + self.lin.cross(&f.lin), lin: self.ang.cross(&f.lin) }
    }

    /// The power `m . f` of a force on a motion.
    #[inline]
    pub fn dot(&self, f: &Force) -> f64 {
        self.ang.dot(&f.ang) + self.lin.dot(&f.lin)
    }
}

/// A rigid transform from frame A to frame B: `rot` maps A coordinates into B
/// coordinates (the library's `R`), and `trans` is B's origin in A
/// coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Transform {
    pub rot: Mat3,
    pub trans: Vec3,
}

impl Default for Transform {
    fn default() -> Self {
        Self::IDENTITY
    }
}

impl Transform {
    pub const IDENTITY: Transform =
        Transform { rot: Mat3::new(1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0), trans: Vec3::new(0.0, 0.0, 0.0) };

    #[inline]
    pub fn new(rot: Mat3, trans: Vec3) -> Self {
        Self { rot, trans }
    }

    pub fn translation(trans: Vec3) -> Self {
        Self { rot: Mat3::identity(), trans }
    }

    pub fn rotation(rot: Mat3) -> Self {
        Self { rot, trans: Vec3::zeros() }
    }

    /// A motion vector given in A, expressed in B.
    #[inline]
    pub fn apply_motion(&self, m: &Motion) -> Motion {
        Motion { ang: self.rot * m.ang, lin: self.rot * (m.lin - self.trans.cross(&m.ang)) }
    }

    /// A motion vector given in B, expressed in A.
    #[inline]
    pub fn inv_apply_motion(&self, m: &Motion) -> Motion {
        let ang = self.rot.tr_mul(&m.ang);
        Motion { ang, lin: self.rot.tr_mul(&m.lin) + self.trans.cross(&ang) }
    }

    /// A force vector given in A, expressed in B.
    #[inline]
    pub fn apply_force(&self, f: &Force) -> Force {
        Force { ang: self.rot * (f.ang - self.trans.cross(&f.lin)), lin: self.rot * f.lin }
    }

    /// A force vector given in B, expressed in A.
    #[inline]
    pub fn inv_apply_force(&self, f: &Force) -> Force {
        let lin = self.rot.tr_mul(&f.lin);
        Force { ang: self.rot.tr_mul(&f.ang) + self.trans.cross(&lin), lin }
    }

    /// `self` maps A to B and `next` maps B to C; the result maps A to C.
    #[inline]
    pub fn then(&self, next: &Transform) -> Transform {
        Transform { rot: next.rot * self.rot, trans: self.trans + self.rot.tr_mul(&next.trans) }
    }

    /// The transform from B back to A.
    pub fn inverse(&self) -> Transform {
        Transform { rot: self.rot.transpose(), trans: -(self.rot * self.trans) }
    }

    /// A point given in A coordinates, expressed in B coordinates.
    #[inline]
    pub fn apply_point(&self, p: &Vec3) -> Vec3 {
        self.rot * (p - self.trans)
    }

    /// A point given in B coordinates, expressed in A coordinates.
    #[inline]
    pub fn inv_apply_point(&self, p: &Vec3) -> Vec3 {
        self.trans + self.rot.tr_mul(p)
    }
}

/// The spatial inertia of a rigid body about a frame's origin: mass `mass`,
/// first moment `h = mass * c` (c the centre of mass), and rotational
/// inertia `rot` about the origin.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RigidInertia {
    pub mass: f64,
    pub h: Vec3,
    pub rot: Mat3,
}

impl Default for RigidInertia {
    fn default() -> Self {
        Self::ZERO
    }
}

impl RigidInertia {
    pub const ZERO: RigidInertia = RigidInertia {
        mass: 0.0,
        h: Vec3::new(0.0, 0.0, 0.0),
        rot: Mat3::new(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0),
    };

    /// A body of `mass` with centre of mass `com` and inertia `inertia_com`
    /// about its centre of mass, all in the frame's coordinates.
    pub fn from_com(mass: f64, com: Vec3, inertia_com: Mat3) -> Self {
        Self { mass, h: com * mass, rot: inertia_com + shift_term(mass, &com) }
    }

    /// Centre of mass (the origin for a massless inertia).
    pub fn com(&self) -> Vec3 {
        if self.mass > 0.0 {
            self.h / self.mass
        } else {
            Vec3::zeros()
        }
    }

    /// Rotational inertia about the centre of mass.
    pub fn inertia_com(&self) -> Mat3 {
        self.rot - shift_term(self.mass, &self.com())
    }

    /// The momentum `I * v`.
    #[inline]
    pub fn apply(&self, v: &Motion) -> Force {
        Force { ang: self.rot * v.ang + self.h.cross(&v.lin), lin: v.lin * self.mass - self.h.cross(&v.ang) }
    }

    /// The same inertia given in frame B, expressed in frame A, with `x`
    /// mapping A to B.
    pub fn expressed_in_parent(&self, x: &Transform) -> RigidInertia {
        let com_b = self.com();
        let com_a = x.inv_apply_point(&com_b);
        let icom_a = x.rot.transpose() * self.inertia_com() * x.rot;
        RigidInertia::from_com(self.mass, com_a, icom_a)
    }

    /// Kinetic energy `v . I v / 2`.
    pub fn kinetic_energy(&self, v: &Motion) -> f64 {
        0.5 * v.dot(&self.apply(v))
    }
}

impl Add for RigidInertia {
    type Output = RigidInertia;
    fn add(self, o: RigidInertia) -> RigidInertia {
        RigidInertia { mass: self.mass + o.mass, h: self.h + o.h, rot: self.rot + o.rot }
    }
}

impl AddAssign for RigidInertia {
    fn add_assign(&mut self, o: RigidInertia) {
        *self = *self + o;
    }
}

/// `E' S E` for a symmetric `S`, computing each symmetric pair once.
#[inline]
fn symmetric_congruence(e: &Mat3, s: &Mat3) -> Mat3 {
    let t = s * e;
    let mut out = Mat3::zeros();
    for i in 0..3 {
        for j in i..3 {
            let v = e[(0, i)] * t[(0, j)] + e[(1, i)] * t[(1, j)] + e[(2, i)] * t[(2, j)];
            out[(i, j)] = v;
            out[(j, i)] = v;
        }
    }
    out
}

/// `m [c]x [c]x' = m (|c|^2 I - c c')`: the parallel-axis term.
fn shift_term(mass: f64, c: &Vec3) -> Mat3 {
    (Mat3::identity() * c.norm_squared() - c * c.transpose()) * mass
}

/// A symmetric 6x6 articulated-body inertia `[A B; B' C]`, mapping a motion
/// `(w, v)` to the force `(A w + B v, B' w + C v)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ArticulatedInertia {
    pub a: Mat3,
    pub b: Mat3,
    pub c: Mat3,
}

impl Default for ArticulatedInertia {
    fn default() -> Self {
        Self { a: Mat3::zeros(), b: Mat3::zeros(), c: Mat3::zeros() }
    }
}

impl From<&RigidInertia> for ArticulatedInertia {
    #[inline]
    fn from(i: &RigidInertia) -> Self {
        Self { a: i.rot, b: super::skew(&i.h), c: Mat3::from_diagonal_element(i.mass) }
    }
}

impl ArticulatedInertia {
    #[inline]
    pub fn apply(&self, v: &Motion) -> Force {
        Force { ang: self.a * v.ang + self.b * v.lin, lin: self.b.tr_mul(&v.ang) + self.c * v.lin }
    }

    /// `self - u u' / d`: removes the part of the inertia that a joint's
    /// free axis does not transmit.
    #[inline]
    pub fn sub_outer(&mut self, u: &Force, inv_d: f64) {
        self.sub_product(&(*u * inv_d), u);
    }

    /// `self - w u'`, for `w u'` symmetric (a sum of such terms over a
    /// joint's axes, `U D^-1 U'`).
    #[inline]
    pub fn sub_product(&mut self, w: &Force, u: &Force) {
        self.a -= w.ang * u.ang.transpose();
        self.b -= w.ang * u.lin.transpose();
        self.c -= w.lin * u.lin.transpose();
    }

    /// The same inertia given in frame B, expressed in frame A, with `x`
    /// mapping A to B: `X' I X`, as a rotation of the blocks (the diagonal
    /// ones symmetric) followed by a shift of the origin by `r`:
    /// `A'' = A' + M + M' - [r]x C' [r]x`, `B'' = B' + [r]x C'`, `C'' = C'`
    /// with `M = [r]x B''`.
    #[inline]
    pub fn expressed_in_parent(&self, x: &Transform) -> ArticulatedInertia {
        let e = &x.rot;
        let a = symmetric_congruence(e, &self.a);
        let c = symmetric_congruence(e, &self.c);
        let b = e.tr_mul(&(self.b * e));
        let r = x.trans;
        // [r]x applied to the columns of a matrix: each column crossed with r.
        let cross_columns = |m: &Mat3| {
            let col = |k: usize| -> Vec3 { r.cross(&m.column(k).into_owned()) };
            Mat3::from_columns(&[col(0), col(1), col(2)])
        };
        let m = cross_columns(&b.transpose());
        let rc = cross_columns(&c);
        // ([r]x C') [r]x = -([r]x ([r]x C')')' since [r]x' = -[r]x.
        let rcr = -cross_columns(&rc.transpose()).transpose();
        let mut a2 = a + m + m.transpose() - rcr;
        // Keep the diagonal blocks exactly symmetric.
        a2 = (a2 + a2.transpose()) * 0.5;
        ArticulatedInertia { a: a2, b: b + rc, c }
    }
}

impl AddAssign for ArticulatedInertia {
    #[inline]
    fn add_assign(&mut self, o: ArticulatedInertia) {
        self.a += o.a;
        self.b += o.b;
        self.c += o.c;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::rotation::axes_rotations;
    use approx::assert_relative_eq;
    use nalgebra::{Matrix6, Vector6};

    fn to6m(m: &Motion) -> Vector6<f64> {
        Vector6::new(m.ang[0], m.ang[1], m.ang[2], m.lin[0], m.lin[1], m.lin[2])
    }
    fn to6f(f: &Force) -> Vector6<f64> {
        Vector6::new(f.ang[0], f.ang[1], f.ang[2], f.lin[0], f.lin[1], f.lin[2])
    }
    fn dense_x(x: &Transform) -> Matrix6<f64> {
        let mut m = Matrix6::zeros();
        let e = x.rot;
        let erx = -e * crate::math::skew(&x.trans);
        m.fixed_view_mut::<3, 3>(0, 0).copy_from(&e);
        m.fixed_view_mut::<3, 3>(3, 3).copy_from(&e);
        m.fixed_view_mut::<3, 3>(3, 0).copy_from(&erx);
        m
    }
    fn dense_i(i: &ArticulatedInertia) -> Matrix6<f64> {
        let mut m = Matrix6::zeros();
        m.fixed_view_mut::<3, 3>(0, 0).copy_from(&i.a);
        m.fixed_view_mut::<3, 3>(0, 3).copy_from(&i.b);
        m.fixed_view_mut::<3, 3>(3, 0).copy_from(&i.b.transpose());
        m.fixed_view_mut::<3, 3>(3, 3).copy_from(&i.c);
        m
    }
    fn sample_transform() -> Transform {
        Transform::new(axes_rotations([1, 2, 3], &Vec3::new(0.3, -0.7, 1.1)), Vec3::new(0.4, -1.2, 0.9))
    }
    fn sample_motion() -> Motion {
        Motion::new(Vec3::new(0.3, -1.0, 2.0), Vec3::new(-0.5, 0.8, 0.1))
    }

    #[test]
    fn transforms_agree_with_dense_plucker_matrices() {
        let x = sample_transform();
        let m = sample_motion();
        let f = Force::new(Vec3::new(1.0, 2.0, -0.5), Vec3::new(0.2, -0.3, 0.7));
        let xd = dense_x(&x);
        assert_relative_eq!(to6m(&x.apply_motion(&m)), xd * to6m(&m), epsilon = 1e-14);
        assert_relative_eq!(to6m(&x.inv_apply_motion(&x.apply_motion(&m))), to6m(&m), epsilon = 1e-14);
        // Force transform is X^{-T}.
        let xf = xd.try_inverse().unwrap().transpose();
        assert_relative_eq!(to6f(&x.apply_force(&f)), xf * to6f(&f), epsilon = 1e-13);
        assert_relative_eq!(to6f(&x.inv_apply_force(&x.apply_force(&f))), to6f(&f), epsilon = 1e-14);
        // Power is invariant.
        assert_relative_eq!(x.apply_motion(&m).dot(&x.apply_force(&f)), m.dot(&f), epsilon = 1e-13);
    }

    #[test]
    fn composition_and_inverse() {
        let x1 = sample_transform();
        let x2 = Transform::new(axes_rotations([3, 1, 3], &Vec3::new(-0.2, 0.5, 0.3)), Vec3::new(1.0, 0.0, -0.4));
        let m = sample_motion();
        let composed = x1.then(&x2);
        assert_relative_eq!(
            to6m(&composed.apply_motion(&m)),
            to6m(&x2.apply_motion(&x1.apply_motion(&m))),
            epsilon = 1e-13
        );
        assert_relative_eq!(to6m(&x1.inverse().apply_motion(&m)), to6m(&x1.inv_apply_motion(&m)), epsilon = 1e-13);
    }

    #[test]
    fn articulated_inertia_transform_is_xt_i_x() {
        let body = RigidInertia::from_com(
            2.5,
            Vec3::new(0.1, 0.3, -0.2),
            Mat3::new(0.3, 0.01, 0.02, 0.01, 0.4, -0.03, 0.02, -0.03, 0.5),
        );
        let mut ia = ArticulatedInertia::from(&body);
        ia.sub_outer(&Force::new(Vec3::new(0.1, 0.2, 0.3), Vec3::new(-0.1, 0.05, 0.2)), 1.0 / 3.0);
        let x = sample_transform();
        let expected = dense_x(&x).transpose() * dense_i(&ia) * dense_x(&x);
        assert_relative_eq!(dense_i(&ia.expressed_in_parent(&x)), expected, epsilon = 1e-12);
        // Rigid inertias transform the same way.
        let rigid_parent = ArticulatedInertia::from(&body.expressed_in_parent(&x));
        let expected = dense_x(&x).transpose() * dense_i(&ArticulatedInertia::from(&body)) * dense_x(&x);
        assert_relative_eq!(dense_i(&rigid_parent), expected, epsilon = 1e-12);
    }

    #[test]
    fn rigid_inertia_momentum_matches_centre_of_mass_form() {
        let m = 2.0;
        let c = Vec3::new(0.5, -0.2, 0.1);
        let ic = Mat3::from_diagonal(&Vec3::new(0.1, 0.2, 0.3));
        let i = RigidInertia::from_com(m, c, ic);
        let v = sample_motion();
        // Velocity of the centre of mass and momentum about the origin.
        let vc = v.lin + v.ang.cross(&c);
        let p = vc * m;
        let l = ic * v.ang + c.cross(&p);
        let f = i.apply(&v);
        assert_relative_eq!(f.lin, p, epsilon = 1e-14);
        assert_relative_eq!(f.ang, l, epsilon = 1e-14);
        assert_relative_eq!(
            i.kinetic_energy(&v),
            0.5 * m * vc.norm_squared() + 0.5 * v.ang.dot(&(ic * v.ang)),
            epsilon = 1e-14
        );
    }
}
