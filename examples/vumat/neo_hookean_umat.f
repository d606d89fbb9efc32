C     neo_hookean_umat.f -- musclefem's built-in compressible neo-Hookean
C     solid (material "neo-hookean") as an Abaqus/Standard UMAT with its
C     analytic Jacobian, written for musclefem's tests and examples
C     (docs/vumat.md, "UMAT"):
C
C        W = mu/2 (I1bar - 3) + (J - 1)**2 / D,
C        sigma = (mu/J) dev(Bbar) + p I,  p = 2 (J - 1)/D,
C        Bbar = J**(-2/3) F F^T,  F = DFGRD1,
C
C     in the global basis, STRESS and DDSDDE in Abaqus/Standard's order
C     11, 22, 33, 12, 13, 23. DDSDDE is the tangent of the Jaumann rate of
C     the Kirchhoff stress divided by J, Abaqus/Standard's definition for
C     finite strain: with b = Bbar, d the identity,
C
C        DDSDDE(ij,kl) = (mu/J) [ (d_ik b_jl + d_il b_jk + b_ik d_jl
C                                  + b_il d_jk)/2
C                                 - 2/3 (b_ij d_kl + d_ij b_kl)
C                                 + 2/9 tr(b) d_ij d_kl ]
C                        + d(J p)/dJ d_ij d_kl,   d(J p)/dJ = 2(2J - 1)/D.
C
C     props(1) = mu [Pa], props(2) = D [1/Pa]; no state variables (those
C     given are carried unchanged). SSE = W [J/m^3 of reference volume].
C
C     Build it into a musclefem material plugin:
C       musclefem umat build examples/vumat/neo_hookean_umat.f
C         --name neo-hookean-umat --props mu=11370:Pa,D=5e-9:1/Pa
C         --out examples/vumat/libneo_hookean_umat.so
C
      subroutine umat(stress, statev, ddsdde, sse, spd, scd,
     1  rpl, ddsddt, drplde, drpldt,
     2  stran, dstran, time, dtime, temp, dtemp, predef, dpred, cmname,
     3  ndi, nshr, ntens, nstatv, props, nprops, coords, drot, pnewdt,
     4  celent, dfgrd0, dfgrd1, noel, npt, layer, kspt, jstep, kinc)
C
      include 'aba_param.inc'
C
      character*80 cmname
      dimension stress(ntens), statev(nstatv), ddsdde(ntens,ntens),
     1  ddsddt(ntens), drplde(ntens), stran(ntens), dstran(ntens),
     2  time(2), predef(1), dpred(1), props(nprops), coords(3),
     3  drot(3,3), dfgrd0(3,3), dfgrd1(3,3), jstep(4)
C
      dimension b(3,3), d(3,3), ii(6), jj(6), intv(1), realv(1)
      character*8 charv(1)
      data ii /1, 2, 3, 1, 1, 2/
      data jj /1, 2, 3, 2, 3, 3/
      data d /1.d0, 0.d0, 0.d0, 0.d0, 1.d0, 0.d0, 0.d0, 0.d0, 1.d0/
C
      if (nprops .ne. 2) then
         intv(1) = nprops
         call stdb_abqerr(-3,
     1     'neo_hookean_umat needs 2 props (mu, D), got %I',
     2     intv, realv, charv)
      end if
      if (ntens .ne. 6) then
         intv(1) = ntens
         call stdb_abqerr(-3,
     1     'neo_hookean_umat is three-dimensional, got ntens = %I',
     2     intv, realv, charv)
      end if
      shear = props(1)
      compr = props(2)
C
C     J = det F and Bbar = J**(-2/3) F F^T
      ajac = dfgrd1(1,1)*(dfgrd1(2,2)*dfgrd1(3,3)
     1                   - dfgrd1(2,3)*dfgrd1(3,2))
     2     - dfgrd1(1,2)*(dfgrd1(2,1)*dfgrd1(3,3)
     3                   - dfgrd1(2,3)*dfgrd1(3,1))
     4     + dfgrd1(1,3)*(dfgrd1(2,1)*dfgrd1(3,2)
     5                   - dfgrd1(2,2)*dfgrd1(3,1))
      scale = ajac**(-2.d0/3.d0)
      do i = 1, 3
         do j = 1, 3
            b(i,j) = scale * (dfgrd1(i,1)*dfgrd1(j,1)
     1             + dfgrd1(i,2)*dfgrd1(j,2) + dfgrd1(i,3)*dfgrd1(j,3))
         end do
      end do
      trace3 = (b(1,1) + b(2,2) + b(3,3)) / 3.d0
      eg = shear / ajac
      press = 2.d0 * (ajac - 1.d0) / compr
      dvol = 2.d0 * (2.d0*ajac - 1.d0) / compr
C
      do m = 1, 6
         i = ii(m)
         j = jj(m)
         stress(m) = eg * (b(i,j) - d(i,j)*trace3) + d(i,j)*press
         do n = 1, 6
            k = ii(n)
            l = jj(n)
            ddsdde(m,n) = eg * (0.5d0 * (d(i,k)*b(j,l) + d(i,l)*b(j,k)
     1                                  + b(i,k)*d(j,l) + b(i,l)*d(j,k))
     2                  - 2.d0/3.d0 * (b(i,j)*d(k,l) + d(i,j)*b(k,l))
     3                  + 2.d0/3.d0 * trace3 * d(i,j)*d(k,l))
     4                  + dvol * d(i,j)*d(k,l)
         end do
      end do
C
      sse = 0.5d0*shear*(3.d0*trace3 - 3.d0)
     1    + (ajac - 1.d0)**2 / compr
C
      return
      end
