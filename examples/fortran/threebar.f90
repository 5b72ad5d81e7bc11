! The paper's three-bar linkage (Figure 1, Section 5) from Fortran: the same
! steps and output as examples/threebar.c. Its analysis at the bifurcation
! R^C (eq. 27-28), the paths out of it, following P1 to R^A and locating it,
! then one lap of the parallelogram mode on an assembly built with
! kinf_create (logical supports, 1-based bars).
program threebar
  use, intrinsic :: iso_c_binding
  use libkin
  implicit none
  real(c_double), parameter :: pi = 3.14159265358979323846_c_double
  type(c_ptr) :: a
  type(kin_analysis) :: an
  type(kin_solve_info) :: si
  type(kin_branch_path) :: paths(4)
  type(kin_locate_options) :: lo
  type(kin_locate_info) :: li
  type(kin_step_info) :: info
  real(c_double) :: sv(3), um(4, 2), ws(3), q(4), betas(2, 2), xyz(2, 4), x0(2, 4), t(4)
  real(c_double) :: d1, d2, d, lap, worst, vrmin, s, closure
  real(c_double), parameter :: p1(4) = [0.0_c_double, 1.0_c_double, 0.0_c_double, 1.0_c_double]
  integer(c_int) :: ns, nsol, nd, k, nsteps, nfact
  character(len=:), allocatable :: msg, what

  call check(kin_model_threebar(KIN_THREEBAR_RC, a), 'create')
  call check(kin_analyse(a, an), 'analyse')
  call check(kin_get_singular_values(a, sv, 3), 'singular values')
  call check(kin_get_mechanisms(a, KIN_MECH_INTERNAL, um, 4, 2), 'mechanisms')
  call check(kin_get_self_stresses(a, ws, 3, 1), 'self-stresses')
  print '(3a)', 'libkin ', kin_version_string(), ': three-bar linkage at R^C (J1 = (1,0), J2 = (2,0))'
  print '(a,i0,a,i0,a,f6.4,1x,f6.4,a)', '  H is ', kin_nfree(a), ' x ', kin_nbars(a), &
    '; singular values ', sv(1), sv(2), ' (paper eq. 27: 1.7321, 1)'
  print '(5(a,i0))', '  r = ', an%rank, ', m = ', an%m, ' (internal ', an%m_internal, &
    ', rigid ', an%m_rigid, '), s = ', an%s
  print '(a)', '  U_m (rows J1x J1y J2x J2y):'
  do k = 1, 4
    print '(4x,f7.4,1x,f7.4)', um(k, 1) + 0.0_c_double, um(k, 2) + 0.0_c_double
  end do
  print '(a,f7.4,1x,f7.4,1x,f7.4,a)', '  W_s: ', ws, ' (eq. 28: 0.5774 0.5774 -0.5774, up to sign)'

  ! the paths out of R^C (eq. 29-33), each followed for l = 1
  call check(kin_second_order(a, KIN_Q_EXACT, 1, q, 4, ns), 'second order')
  call check(kin_quadrics_scan(2, ns, q, 64, 1_c_long, betas, 2, nsol, si), 'scan')
  call check(kin_branch_paths(a, betas, nsol, 1.0_c_double, paths, c_null_ptr, nd), 'paths')
  print '(a,i0,a,i0,a)', '  second order: ', nsol, ' real solutions (eq. 33), ', nd, &
    ' distinct directed paths:'
  do k = 1, nsol
    d1 = um(2, 1) * betas(1, k) + um(2, 2) * betas(2, k)
    d2 = um(4, 1) * betas(1, k) + um(4, 2) * betas(2, k)
    if (abs(d1) < 1e-9_c_double) then
      what = 'J1 held at S2 (Figure 1(d))'
    else
      what = 'parallelogram P1 (Figure 1(b))'
    end if
    print '(a,i0,a,f7.4,a,f7.4,2a)', '    beta ', k - 1, ': (dJ1y, dJ2y) = (', d1 + 0.0_c_double, &
      ', ', d2 + 0.0_c_double, ')  ', what
  end do

  ! Section 5: follow P1 from R^C to R^A and locate it
  call kin_locate_options_default(lo)
  lo%delta = 0.1_c_double
  call check(kin_path_set_direction(a, p1, 4), 'direction')
  call check(kin_step(a, 1e-3_c_double, info), 'step')
  call check(kin_locate_next(a, lo, li), 'locate')
  call check(kin_get_coords(a, x0), 'coords')
  print '(a,i0,a,i0,a)', '  along P1 to the next bifurcation: ', li%steps, &
    ' steps, then located with ', li%factorizations, ' factorizations:'
  if (li%v_r_rel < 1e-14_c_double) li%v_r_rel = 0
  print '(a,f9.6,a,f9.6,a,f9.6,a,f9.6,a,es7.1,a,i0,a,i0)', '    J1 = (', x0(1, 1) + 0.0_c_double, &
    ', ', x0(2, 1) + 0.0_c_double, '), J2 = (', x0(1, 2) + 0.0_c_double, ', ', &
    x0(2, 2) + 0.0_c_double, '): R^A, vanishing v_r / v_max = ', li%v_r_rel, ', m = ', &
    li%m_internal, ', s = ', li%s
  call kin_assembly_free(a)

  ! a lap of the parallelogram mode from J1 at 60 degrees: joints J1, J2,
  ! S1, S2 as columns, bars S1-J1, J1-J2, J2-S2 numbered from 1
  xyz = reshape([cos(pi / 3), sin(pi / 3), cos(pi / 3) + 1, sin(pi / 3), 0.0_c_double, &
                 0.0_c_double, 1.0_c_double, 0.0_c_double], [2, 4])
  if (kinf_create(xyz, reshape([3, 1, 1, 2, 2, 4], [2, 3]), a, &
                  fixed=reshape([.false., .false., .false., .false., .true., .true., .true., .true.], &
                                [2, 4]), &
                  rest_lengths=[1.0_c_double, 1.0_c_double, 1.0_c_double], one_based=.true., &
                  errmsg=msg) /= KIN_OK) then
    write (*, '(2a)') 'create: ', msg
    error stop 1
  end if
  call check(kin_get_coords(a, x0), 'coords')
  lap = 2 * sqrt(2.0_c_double) * pi ! J1 and J2 both travel 2*pi
  nsteps = 0
  nfact = 0
  worst = 0
  vrmin = 1e300_c_double
  print '(a)', ''
  print '(a)', 'lap of the parallelogram mode, starting at J1 = (0.5, 0.866):'
  print '(2x,a5,1x,a10,1x,a10,1x,a10,1x,a12)', 'step', 'l', 'theta', 'v_r', 'strain'
  do while (kin_path_length(a) < lap - 0.15_c_double)
    call check(kin_step(a, 0.1_c_double, info), 'step')
    nsteps = nsteps + 1
    nfact = nfact + info%factorizations
    s = kin_max_strain(a)
    worst = max(worst, s)
    vrmin = min(vrmin, info%v_r)
    call check(kin_get_coords(a, xyz), 'coords')
    if (mod(nsteps, 10) == 0) print '(2x,i5,1x,f10.5,1x,f10.5,1x,es10.3,1x,es12.3)', nsteps, &
      info%l, atan2(xyz(2, 1), xyz(1, 1)) * 180 / pi, info%v_r, s
  end do
  ! land on the start: aim along the tangent
  do k = 1, 3
    call check(kin_get_tangent(a, t, 4), 'tangent')
    call check(kin_get_coords(a, xyz), 'coords')
    d = dot_product(t, reshape(x0(:, 1:2) - xyz(:, 1:2), [4]))
    if (abs(d) < 1e-15_c_double) exit
    if (kin_step(a, d, info) /= KIN_OK) exit
    nsteps = nsteps + 1
    nfact = nfact + info%factorizations
  end do
  call check(kin_get_coords(a, xyz), 'coords')
  closure = maxval(abs(xyz(:, 1:2) - x0(:, 1:2)))
  print '(2(a,i0),a,f8.6,a,f8.6,a)', '  ', nsteps, ' steps, ', nfact, &
    ' factorizations, path length ', kin_path_length(a), ' (2*sqrt(2)*pi = ', lap, ')'
  if (closure < 1e-12_c_double) then
    what = 'below'
  else
    what = 'ABOVE'
  end if
  print '(a,es7.1,a,es9.3,3a)', '  max bar strain ', worst, ' (tolerance 1e-12), smallest v_r ', &
    vrmin, ', closure error ', what, ' 1e-12'
  call kin_assembly_free(a)
  ! a main program's variables are saved (never freed at its end): free the
  ! strings, so a leak checker sees no leak that is not libkin's
  if (allocated(msg)) deallocate(msg)
  if (allocated(what)) deallocate(what)

contains

  ! Stop with the handle's message (or the status message) on failure.
  subroutine check(status, step)
    integer(c_int), intent(in) :: status
    character(len=*), intent(in) :: step
    if (status == KIN_OK) return
    if (c_associated(a)) then
      write (*, '(4a)') step, ': ', kin_last_error(a), ''
    else
      write (*, '(4a)') step, ': ', kin_strerror(status), ''
    end if
    error stop 1
  end subroutine

end program threebar
