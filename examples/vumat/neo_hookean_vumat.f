C     neo_hookean_vumat.f -- musclefem's built-in compressible neo-Hookean
C     solid (material "neo-hookean") as an Abaqus/Explicit VUMAT, written
C     for musclefem's tests and examples (docs/vumat.md):
C
C        W = mu/2 (I1bar - 3) + (J - 1)**2 / D,
C        sigma = (mu/J) dev(Bbar) + 2 (J - 1)/D I,  Bbar = J**(-2/3) B.
C
C     Everything is computed in the co-rotational frame from the stretch
C     tensor U = stretchNew, where R^T B R = U U and J = det U, so the
C     stress is the co-rotational stress Abaqus/Explicit expects.
C     props(1) = mu [Pa], props(2) = D [1/Pa]; state variables are carried
C     through unchanged. The specific internal energy grows by the stress
C     power of the increment, (stressOld + stressNew)/2 : strainInc over
C     the density.
C
C     Build it into a musclefem material plugin:
C       musclefem vumat build examples/vumat/neo_hookean_vumat.f
C         --name neo-hookean-vumat --props mu=11370:Pa,D=5e-9:1/Pa
C         --out examples/vumat/libneo_hookean_vumat.so
C
      subroutine vumat(
     1  nblock, ndir, nshr, nstatev, nfieldv, nprops, lanneal,
     2  stepTime, totalTime, dt, cmname, coordMp, charLength,
     3  props, density, strainInc, relSpinInc,
     4  tempOld, stretchOld, defgradOld, fieldOld,
     5  stressOld, stateOld, enerInternOld, enerInelasOld,
     6  tempNew, stretchNew, defgradNew, fieldNew,
     7  stressNew, stateNew, enerInternNew, enerInelasNew)
C
      include 'vaba_param.inc'
C
      dimension props(nprops), density(nblock), coordMp(nblock,*),
     1  charLength(nblock), strainInc(nblock,ndir+nshr),
     2  relSpinInc(nblock,nshr), tempOld(nblock),
     3  stretchOld(nblock,ndir+nshr),
     4  defgradOld(nblock,ndir+nshr+nshr),
     5  fieldOld(nblock,nfieldv), stressOld(nblock,ndir+nshr),
     6  stateOld(nblock,nstatev), enerInternOld(nblock),
     7  enerInelasOld(nblock), tempNew(nblock),
     8  stretchNew(nblock,ndir+nshr),
     9  defgradNew(nblock,ndir+nshr+nshr),
     1  fieldNew(nblock,nfieldv),
     2  stressNew(nblock,ndir+nshr), stateNew(nblock,nstatev),
     3  enerInternNew(nblock), enerInelasNew(nblock)
      character*80 cmname
C
      dimension intv(1), realv(1)
      character*8 charv(1)
C
      if (nprops .ne. 2) then
         intv(1) = nprops
         call xplb_abqerr(-3,
     1     'neo_hookean_vumat needs 2 props (mu, D), got %I',
     2     intv, realv, charv)
      end if
      shear = props(1)
      compr = props(2)
C
      do k = 1, nblock
         u11 = stretchNew(k,1)
         u22 = stretchNew(k,2)
         u33 = stretchNew(k,3)
         u12 = stretchNew(k,4)
         u23 = stretchNew(k,5)
         u31 = stretchNew(k,6)
C        Bhat = U U (symmetric) and J = det U
         b11 = u11*u11 + u12*u12 + u31*u31
         b22 = u12*u12 + u22*u22 + u23*u23
         b33 = u31*u31 + u23*u23 + u33*u33
         b12 = u11*u12 + u12*u22 + u31*u23
         b23 = u12*u31 + u22*u23 + u23*u33
         b31 = u31*u11 + u23*u12 + u33*u31
         ajac = u11*(u22*u33 - u23*u23) - u12*(u12*u33 - u23*u31)
     1        + u31*(u12*u23 - u22*u31)
C        (mu/J) J**(-2/3) dev(Bhat) + p I
         scale = shear / ajac * ajac**(-2.d0/3.d0)
         trace3 = (b11 + b22 + b33) / 3.d0
         press = 2.d0 * (ajac - 1.d0) / compr
         stressNew(k,1) = scale*(b11 - trace3) + press
         stressNew(k,2) = scale*(b22 - trace3) + press
         stressNew(k,3) = scale*(b33 - trace3) + press
         stressNew(k,4) = scale*b12
         stressNew(k,5) = scale*b23
         stressNew(k,6) = scale*b31
C
         power = 0.d0
         do i = 1, ndir
            power = power + (stressOld(k,i) + stressNew(k,i))
     1                      * strainInc(k,i)
         end do
         do i = ndir + 1, ndir + nshr
            power = power + 2.d0 * (stressOld(k,i) + stressNew(k,i))
     1                      * strainInc(k,i)
         end do
         enerInternNew(k) = enerInternOld(k) + 0.5d0*power/density(k)
         enerInelasNew(k) = enerInelasOld(k)
         do i = 1, nstatev
            stateNew(k,i) = stateOld(k,i)
         end do
      end do
C
      return
      end
