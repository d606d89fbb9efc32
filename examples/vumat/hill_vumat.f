C     hill_vumat.f -- musclefem's built-in Hill-type active muscle
C     (material "hill", seed paper section 2.1, Eqs. 1-23, Table 1, read
C     as crates/materials/src/hill documents) as an Abaqus/Explicit VUMAT,
C     written for musclefem's tests and examples (docs/vumat.md):
C
C       W = c [exp(b (I1bar - 3)) - 1] + W_f(lf) + (J - 1)**2 / D,
C       sigma = (1/J) dev[2 W1 Bbar + (sPE + sSEE)/lf g g] + 2 (J-1)/D I,
C
C     g = J**(-1/3) F a0 the isochoric fiber, lf = |g| its stretch,
C     W1 = b c exp(b (I1bar - 3)); the parallel element
C     sPE = sigma0 A (lf - lambda_pe)**2 beyond lambda_pe; the series
C     element sSEE = beta [exp(alpha (ls - 1)) - 1] in series with the
C     contractile element sCE = sigma0 f_l(lf_old/lambda_opt) f_v f_t,
C     (1 + k) lf = lm + k ls, solved each increment for the SEE stretch.
C
C     The fiber is local direction 1 (build with --fiber orientation, the
C     default): in the co-rotational frame g = J**(-1/3) U e1 and
C     Bbar = J**(-2/3) U U, with U = stretchNew.
C     props (19), in this order: D, b, c, A, lambda_pe, sigma0, alpha,
C       beta, lambda_opt, k, k_c, k_e, d, lambda_dot_min, S, n1, n2,
C       t0, t1 (the built-in's parameters, same names and units).
C     State variables (3): lambda_m, lambda_s, sigma_SEE, initially
C       1, 1, 0 (build with --statev-initial 1,1,0).
C     f_t is the activation at the end of the increment,
C     totalTime + dt; with dt = 0 the whole fiber stretch increment goes
C     into the SEE (the contractile element cannot move in no time).
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
      dimension intv(2), realv(3), g(3), b(6), sm(6)
      character*8 charv(1)
C
      if (nprops .ne. 19 .or. nstatev .lt. 3) then
         intv(1) = nprops
         intv(2) = nstatev
         call xplb_abqerr(-3,
     1     'hill_vumat needs 19 props and 3 state variables, got %I '//
     2     'and %I', intv, realv, charv)
      end if
      compr = props(1)
      bexp = props(2)
      cmat = props(3)
      apar = props(4)
      plpe = props(5)
      sig0 = props(6)
      alph = props(7)
      beta = props(8)
      plopt = props(9)
      rk = props(10)
      act = hill_activation(totalTime + dt, props(15), props(16),
     1  props(17), props(18), props(19))
C
      do k = 1, nblock
C        fiber stretch at the end and at the start of the increment
         call hill_fiber(stretchNew, nblock, k, ajac, g, flam)
         call hill_fiber(stretchOld, nblock, k, ajaco, b, flamo)
         slm = stateOld(k,1)
         sls = stateOld(k,2)
         ssee = stateOld(k,3)
         if (.not. (sls .gt. 0.d0 .and. ssee .gt. -beta)) then
            realv(1) = slm
            realv(2) = sls
            realv(3) = ssee
            call xplb_abqerr(-3,
     1        'hill_vumat: state (%R, %R, %R) needs lambda_s > 0 '//
     2        'and sigma_SEE > -beta', intv, realv, charv)
         end if
C        the series and contractile elements
         active = sig0 * hill_force_length(flamo / plopt) * act
         w1 = (1.d0 + rk)*flam - slm - rk*sls
         call hill_series(props, dt, sls, ssee, w1, active,
     1     delta, sseen)
         slsn = sls + delta
         stateNew(k,1) = (1.d0 + rk)*flam - rk*slsn
         stateNew(k,2) = slsn
         stateNew(k,3) = sseen
         do i = 4, nstatev
            stateNew(k,i) = stateOld(k,i)
         end do
C        fiber stress: parallel + series elements
         pe = 0.d0
         if (flam .gt. plpe) pe = sig0 * apar * (flam - plpe)**2
         ratio = (pe + sseen) / flam
C        M = 2 W1 Bbar + ratio g g, Bbar = J**(-2/3) U U
         call hill_bbar(stretchNew, nblock, k, ajac, b)
         ai1 = b(1) + b(2) + b(3)
         w1m = bexp * cmat * exp(bexp * (ai1 - 3.d0))
         sm(1) = 2.d0*w1m*b(1) + ratio*g(1)*g(1)
         sm(2) = 2.d0*w1m*b(2) + ratio*g(2)*g(2)
         sm(3) = 2.d0*w1m*b(3) + ratio*g(3)*g(3)
         sm(4) = 2.d0*w1m*b(4) + ratio*g(1)*g(2)
         sm(5) = 2.d0*w1m*b(5) + ratio*g(2)*g(3)
         sm(6) = 2.d0*w1m*b(6) + ratio*g(3)*g(1)
         trace3 = (sm(1) + sm(2) + sm(3)) / 3.d0
         pvol = ajac * 2.d0 * (ajac - 1.d0) / compr
         do i = 1, 3
            stressNew(k,i) = (sm(i) - trace3 + pvol) / ajac
         end do
         do i = 4, 6
            stressNew(k,i) = sm(i) / ajac
         end do
C        specific internal energy: the stress power of the increment
         power = 0.d0
         do i = 1, 6
            wt = 1.d0
            if (i .gt. 3) wt = 2.d0
            power = power + wt*(stressOld(k,i) + stressNew(k,i))
     1                      * strainInc(k,i)
         end do
         enerInternNew(k) = enerInternOld(k) + 0.5d0*power/density(k)
         enerInelasNew(k) = enerInelasOld(k)
      end do
      return
      end
C
C     J = det U, g = J**(-1/3) U e1 and lf = |g| of point k of U
C     (Abaqus order 11, 22, 33, 12, 23, 31).
      subroutine hill_fiber(u, nblock, k, ajac, g, flam)
      include 'vaba_param.inc'
      dimension u(nblock,6), g(3)
      ajac = u(k,1)*(u(k,2)*u(k,3) - u(k,5)*u(k,5))
     1     - u(k,4)*(u(k,4)*u(k,3) - u(k,5)*u(k,6))
     2     + u(k,6)*(u(k,4)*u(k,5) - u(k,2)*u(k,6))
      scale = ajac**(-1.d0/3.d0)
      g(1) = scale*u(k,1)
      g(2) = scale*u(k,4)
      g(3) = scale*u(k,6)
      flam = sqrt(g(1)*g(1) + g(2)*g(2) + g(3)*g(3))
      return
      end
C
C     Bbar = J**(-2/3) U U of point k (Abaqus order).
      subroutine hill_bbar(u, nblock, k, ajac, b)
      include 'vaba_param.inc'
      dimension u(nblock,6), b(6)
      u11 = u(k,1)
      u22 = u(k,2)
      u33 = u(k,3)
      u12 = u(k,4)
      u23 = u(k,5)
      u31 = u(k,6)
      scale = ajac**(-2.d0/3.d0)
      b(1) = scale*(u11*u11 + u12*u12 + u31*u31)
      b(2) = scale*(u12*u12 + u22*u22 + u23*u23)
      b(3) = scale*(u31*u31 + u23*u23 + u33*u33)
      b(4) = scale*(u11*u12 + u12*u22 + u31*u23)
      b(5) = scale*(u12*u31 + u22*u23 + u23*u33)
      b(6) = scale*(u31*u11 + u23*u12 + u33*u31)
      return
      end
C
C     Force-length relation f_l(r), r = lf / lambda_opt (Eq. 10).
      double precision function hill_force_length(r)
      include 'vaba_param.inc'
      if (r .lt. 0.4d0) then
         hill_force_length = 0.d0
      else if (r .lt. 0.6d0) then
         hill_force_length = 9.d0*(r - 0.4d0)**2
      else if (r .lt. 1.4d0) then
         hill_force_length = 1.d0 - 4.d0*(1.d0 - r)**2
      else if (r .lt. 1.6d0) then
         hill_force_length = 9.d0*(r - 1.6d0)**2
      else
         hill_force_length = 0.d0
      end if
      return
      end
C
C     Activation f_t(t) (Eq. 12): n1 before t0, rising towards n2 at rate
C     S until t1, then decaying back towards n1.
      double precision function hill_activation(t, s, an1, an2, t0, t1)
      include 'vaba_param.inc'
      span = an2 - an1
      if (t .le. t0) then
         hill_activation = an1
      else if (t .le. t1) then
         hill_activation = an1 + span*(1.d0 - exp(-s*(t - t0)))
      else
         reach = span*(1.d0 - exp(-s*(t1 - t0)))
         hill_activation = an1 + reach
     1                   - reach*(1.d0 - exp(-s*(t - t1)))
      end if
      return
      end
C
C     Force-velocity relation f_v and its slope at the CE stretch rate
C     rate (Eq. 11): shortening (rate <= 0) and lengthening branches.
      subroutine hill_force_velocity(rate, rkc, rke, dd, rdmin, fv, dfv)
      include 'vaba_param.inc'
      r = rate / rdmin
      if (rate .le. 0.d0) then
         q = 1.d0 / (1.d0 + rkc*r)
         fv = (1.d0 - r)*q
         dfv = -(1.d0 + rkc)*q*q / rdmin
      else
         ckk = rkc*rke
         q = 1.d0 / (1.d0 - ckk*r)
         fv = dd - (dd - 1.d0)*(1.d0 + r)*q
         dfv = -(dd - 1.d0)*(1.d0 + ckk)*q*q / rdmin
      end if
      return
      end
C
C     The SEE stretch increment delta of one increment: sSEE = sCE, i.e.
C       h(delta) = (ssee + beta) exp(alpha delta) - beta
C                  - active f_v((w1 - k delta)/dt) = 0,
C     h increasing, its root inside [lower, upper] where sSEE is 0 or
C     w1/k (lower) and active sup f_v (upper): Newton's method, bisection
C     whenever a step would leave the bracket, to |step| <= 1e-12/alpha.
      subroutine hill_series(props, dt, sls, ssee, w1, active,
     1  delta, sseen)
      include 'vaba_param.inc'
      dimension props(19)
      alph = props(7)
      beta = props(8)
      rk = props(10)
      rkc = props(11)
      rke = props(12)
      dd = props(13)
      rdmin = props(14)
      sb = ssee + beta
      if (active .le. 0.d0) then
         delta = 1.d0 - sls
         sseen = 0.d0
         return
      end if
      if (dt .le. 0.d0) then
         delta = w1 / rk
         sseen = sb*exp(alph*delta) - beta
         return
      end if
      tol = 1.d-12 / alph
      sup = dd + (dd - 1.d0)/(rkc*rke)
      blow = min(w1/rk, log(beta/sb)/alph)
      bup = log((active*sup + beta)/sb)/alph
      delta = max(blow, min(0.d0, bup))
      do it = 1, 200
         grown = sb*exp(alph*delta)
         call hill_force_velocity((w1 - rk*delta)/dt, rkc, rke, dd,
     1     rdmin, fv, dfv)
         h = grown - beta - active*fv
         dh = alph*grown + active*dfv*rk/dt
         if (h .lt. 0.d0) then
            blow = delta
         else
            bup = delta
         end if
         step = -h/dh
         cand = delta + step
         if (dh .gt. 0.d0 .and. cand .ge. blow .and. cand .le. bup) then
            delta = cand
            if (abs(step) .le. tol) exit
         else
            delta = 0.5d0*(blow + bup)
         end if
         if (bup - blow .le. tol) exit
      end do
      sseen = sb*exp(alph*delta) - beta
      return
      end
