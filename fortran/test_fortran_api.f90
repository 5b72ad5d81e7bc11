! The Fortran layer of module libkin: strings, wrappers (shapes, logical
! supports, 1-based indices), the constants against the library, and the
! error paths of the wrappers. Asserts outcomes (status codes, counts,
! values), never message text.
program test_fortran_api
  use, intrinsic :: iso_c_binding
  use libkin
  implicit none
  integer :: failures = 0
  call test_strings()
  call test_threebar()
  call test_create_errors()
  call test_sail()
  call test_progress()
  call test_io()
  if (failures /= 0) then
    print '(i0,a)', failures, ' checks failed'
    error stop 1
  end if
  print '(a)', 'test_fortran_api: all checks passed'

contains

  subroutine expect(ok, what)
    logical, intent(in) :: ok
    character(len=*), intent(in) :: what
    if (.not. ok) then
      print '(2a)', 'FAILED: ', what
      failures = failures + 1
    end if
  end subroutine

  subroutine test_strings()
    integer(c_int) :: k
    call expect(kin_version_number() == KIN_MODULE_VERSION_NUMBER, 'module and library versions agree')
    call expect(kin_version_string() == KIN_MODULE_VERSION_STRING, 'version strings agree')
    call expect(KIN_MODULE_VERSION_NUMBER == &
                KIN_VERSION_MAJOR * 10000 + KIN_VERSION_MINOR * 100 + KIN_VERSION_PATCH, 'version parts')
    call expect(KIN_OK == 0 .and. KIN_STATUS_COUNT > KIN_EFORMAT, 'status constants')
    ! every generated code is one the library knows, by the same name
    do k = 0, KIN_STATUS_COUNT - 1
      call expect(kin_status_name(k) /= 'KIN_UNKNOWN' .and. len(kin_strerror(k)) > 0, 'known code')
    end do
    call expect(kin_status_name(KIN_EINVAL) == 'KIN_EINVAL', 'name of KIN_EINVAL')
    call expect(kin_status_name(KIN_STATUS_COUNT) == 'KIN_UNKNOWN', 'code past the list is unknown')
    call expect(len(kin_last_error(c_null_ptr)) > 0, 'NULL handle has a static message')
  end subroutine

  subroutine test_threebar()
    type(c_ptr) :: a, b
    integer(c_int) :: bars(2, 3), got(2, 3), small(2, 2), ns, nsol, mult(2)
    logical :: fixed(2, 4), gotfixed(2, 4)
    real(c_double) :: xyz(2, 4), h(4, 3), lengths(3), tau, res, q(4), betas(2, 2)
    type(kin_options) :: o, o2
    type(kin_analysis) :: an
    type(kin_homotopy_info) :: hi
    type(kin_locate_info) :: li
    character(len=:), allocatable :: msg
    ! R^C: J1 = (1,0), J2 = (2,0), supports S1 = (0,0), S2 = (1,0)
    xyz = reshape([1d0, 0d0, 2d0, 0d0, 0d0, 0d0, 1d0, 0d0], [2, 4])
    bars = reshape([3, 1, 1, 2, 2, 4], [2, 3])
    fixed = .false.
    fixed(:, 3:4) = .true.
    call expect(kinf_create(xyz, bars, a, fixed=fixed, one_based=.true., errmsg=msg) == KIN_OK, 'create')
    call expect(len(msg) == 0, 'no message on success')
    call expect(kin_dim(a) == 2 .and. kin_njoints(a) == 4 .and. kin_nbars(a) == 3 .and. &
                kin_nfree(a) == 4, 'sizes from the array shapes')
    call expect(kinf_get_bars(a, got, one_based=.true.) == KIN_OK, 'get bars')
    call expect(all(got == bars), 'bars 1-based as given')
    call expect(kinf_get_bars(a, got) == KIN_OK, 'get bars 0-based')
    call expect(all(got == bars - 1), 'bars 0-based')
    got = -7
    call expect(kin_get_bars(a, got) == KIN_OK, 'raw get bars')
    call expect(all(got == bars - 1), 'raw bars')
    call expect(kinf_get_bars(a, small) == KIN_ERANGE, 'bars array too small')
    call expect(kinf_get_bars(c_null_ptr, got) == KIN_ENULL, 'bars of a NULL handle')
    call expect(kinf_get_fixed(a, gotfixed) == KIN_OK, 'get fixed')
    call expect(all(gotfixed .eqv. fixed), 'supports as logicals')
    call expect(kinf_get_fixed(a, gotfixed(:, 1:3)) == KIN_ERANGE, 'fixed of the wrong shape')
    call expect(kinf_free_index(a, 2, 2, one_based=.true.) == 4, 'J2y is free row 4 (1-based)')
    call expect(kinf_free_index(a, 3, 1, one_based=.true.) == 0, 'support: no row (1-based)')
    call expect(kinf_free_index(a, 1, 0) == 2 .and. kin_free_index(a, 2, 0) == -1, 'raw rows')
    call expect(kin_get_rest_lengths(a, lengths) == KIN_OK, 'rest lengths')
    call expect(all(abs(lengths - 1) < 1d-15), 'initial lengths kept')
    call expect(kin_get_equilibrium_matrix(a, h, 4) == KIN_OK, 'H')
    call expect(kin_get_equilibrium_matrix(a, h, 3) == KIN_ERANGE, 'ldh < nfree')
    call expect(kin_analyse(a, an) == KIN_OK, 'analyse')
    call expect(an%rank == 2 .and. an%m_internal == 2 .and. an%s == 1, 'R^C analysis (eq. 27)')
    ! the exact R^C: a proven singular point (kin_locate_info layout 3) within rounding
    call expect(kin_prove_singular(a, li) == KIN_OK .and. li%sing_proven == 1 .and. li%sing_corank == 1, &
                'R^C proven singular')
    call expect(li%sing_distance < 1d-12 .and. li%sing_dlength < 1d-12, 'R^C: bounds at rounding level')
    ! options through the bind(C) type
    call kin_options_default(o)
    call expect(o%factorization == KIN_STEP_SVD .and. o%rank_tol == 1d-9, 'default options')
    o%corrector_tol = 1d-11
    call expect(kin_set_options(a, o) == KIN_OK, 'set options')
    call expect(kin_get_options(a, o2) == KIN_OK, 'get options')
    call expect(o2%corrector_tol == 1d-11, 'options round trip')
    o%rank_tol = -1
    call expect(kin_set_options(a, o) == KIN_EINVAL, 'bad options')
    call expect(len(kin_last_error(a)) > 0, 'bad options: a message')
    ! second order and the complete solver: two real directions at R^C (eq. 33)
    call expect(kin_analyse(a, an) == KIN_OK, 'analyse again')
    call expect(kin_second_order(a, KIN_Q_EXACT, 1, q, 4, ns) == KIN_OK, 'Q')
    call expect(ns == 1, 'one quadric')
    call expect(kin_quadrics_homotopy(2, ns, q, 7_c_long, 1, betas, 2, nsol, mult, hi) == KIN_OK, &
                'homotopy')
    call expect(hi%paths == 2 .and. hi%real_distinct == 2 .and. nsol == 2, 'two real solutions')
    call expect(kin_test_function(a, tau) == KIN_OK, 'test function')
    call expect(tau == 0, 'tau vanishes at a bifurcation')
    call expect(kin_assembly_clone(a, b) == KIN_OK, 'clone')
    call expect(kin_nfree(b) == 4, 'clone sizes')
    call expect(kin_relax(b, 5, res) == KIN_OK, 'relax')
    call expect(res <= 1d-12, 'relax a strain-free state')
    call expect(kin_relax(b, 0, res) == KIN_EINVAL, 'relax with max_iter 0')
    call kin_assembly_free(b)
    call kin_assembly_free(a)
  end subroutine

  subroutine test_create_errors()
    type(c_ptr) :: a
    real(c_double) :: xyz(2, 4)
    character(len=:), allocatable :: msg
    xyz = reshape([1d0, 0d0, 2d0, 0d0, 0d0, 0d0, 1d0, 0d0], [2, 4])
    call expect(kinf_create(xyz, reshape([3, 1, 1, 2, 2, 4], [3, 2]), a, errmsg=msg) == KIN_ERANGE &
                .and. .not. c_associated(a) .and. len(msg) > 0, 'bars not (2, nbars)')
    call expect(kinf_create(xyz, reshape([3, 1, 1, 2, 2, 4], [2, 3]), a, &
                            fixed=reshape([.true., .true.], [2, 1]), errmsg=msg) == KIN_ERANGE, &
                'fixed not shaped like xyz')
    call expect(kinf_create(xyz, reshape([3, 1, 1, 2, 2, 4], [2, 3]), a, &
                            rest_lengths=[1d0, 1d0], errmsg=msg) == KIN_ERANGE, 'rest lengths')
    call expect(kinf_create(xyz, reshape([3, 1, 1, 2, 2, 5], [2, 3]), a, one_based=.true., &
                            errmsg=msg) == KIN_EJOINT .and. .not. c_associated(a) .and. len(msg) > 0, &
                'joint 5 of 4 (1-based): C error with its message')
    ! a free unit square (closed four-bar)
    xyz = reshape([0d0, 0d0, 1d0, 0d0, 1d0, 1d0, 0d0, 1d0], [2, 4])
    call expect(kinf_create(xyz, reshape([0, 1, 1, 2, 2, 3, 3, 0], [2, 4]), a) == KIN_OK, &
                'no supports given')
    call expect(kin_nfree(a) == 8, 'fixed absent: every coordinate free')
    call kin_assembly_free(a)
  end subroutine

  ! the square sail's flat state: 4 symmetries (the half turn and the mirror
  ! z -> -z), the identity first; room for 3 is too little
  subroutine test_symmetries(a)
    type(c_ptr), value :: a
    integer(c_int) :: perm(4 * 64), ns, ng, m
    real(c_double) :: q(9 * 4), t(3 * 4), r(4 * 64 * 64)
    type(kin_analysis) :: an
    call expect(kin_symmetries(a, 4, perm, q, t, ns) == KIN_OK .and. ns == 4, 'symmetries')
    call expect(all(q(1:9) == [1d0, 0d0, 0d0, 0d0, 1d0, 0d0, 0d0, 0d0, 1d0]), 'identity first')
    call expect(kin_symmetries(a, 3, perm, q, t, ns) == KIN_ERANGE .and. ns == 4, 'symmetries: room')
    call expect(kin_mechanism_group(a, 4, r, ng) == KIN_OK .and. ng == 4, 'mechanism group')
    call expect(kin_get_analysis(a, an) == KIN_OK, 'analysis')
    m = an%m_internal
    call expect(m > 0 .and. abs(r(1) - 1d0) < 1d-12 .and. abs(r(m * m) - 1d0) < 1d-12, 'R_1 = I')
    call expect(kin_mechanism_group(a, 0, r, ng) == KIN_EINVAL .and. ng == 0, 'mechanism group: max_group')
  end subroutine

  subroutine test_sail()
    type(kin_sail_params) :: p
    type(c_ptr) :: a
    integer(c_int) :: nj, nb
    character(len=:), allocatable :: msg
    call kin_sail_params_default(p, 4, 1)
    call expect(kin_sail_size(p, nj, nb) == KIN_OK .and. nj > 0 .and. nb > 0, 'sail size')
    call expect(kinf_model_sail(p, a, widths=[0.5d0, 0.5d0]) == KIN_ERANGE, 'widths of n_loops')
    call expect(kinf_model_sail(p, a, widths=[0.5d0], errmsg=msg) == KIN_OK .and. &
                kin_njoints(a) == nj .and. kin_nbars(a) == nb, 'sail with widths')
    call test_symmetries(a)
    call kin_assembly_free(a)
    p%n_sides = 2
    call expect(kinf_model_sail(p, a, errmsg=msg) == KIN_EINVAL .and. len(msg) > 0 .and. &
                .not. c_associated(a), 'bad sail: status and message')
  end subroutine

  ! Progress callback for the tests: counts its calls in the integer that
  ! user points to; cancels when that count is negative.
  integer(c_int) function count_calls(user, done, total) bind(C)
    type(c_ptr), value :: user
    real(c_double), value :: done, total
    integer(c_int), pointer :: calls
    call c_f_pointer(user, calls)
    count_calls = 0
    if (calls < 0) then
      count_calls = 1
      return
    end if
    if (done >= 0 .and. done <= total) calls = calls + 1
  end function

  subroutine test_progress()
    type(c_ptr) :: a
    type(kin_analysis) :: an
    type(kin_homotopy_options) :: ho
    type(kin_homotopy_info) :: hi
    ! volatile: the callback changes it through the C pointer in ho%user
    integer(c_int), target, volatile :: calls
    integer(c_int) :: ns, nsol, mult(2)
    real(c_double) :: q(4), betas(2, 2)
    ! the compiler checks count_calls against the abstract interface here
    procedure(kin_progress_callback), pointer :: fn
    fn => count_calls
    call expect(associated(fn), 'callback has the kin_progress_callback interface')
    call expect(kin_model_threebar(KIN_THREEBAR_RC, a) == KIN_OK, 'three-bar')
    call expect(kin_analyse(a, an) == KIN_OK, 'analyse')
    call expect(kin_second_order(a, KIN_Q_EXACT, 1, q, 4, ns) == KIN_OK, 'Q')
    call expect(kin_set_progress(a, c_funloc(count_calls), c_null_ptr) == KIN_OK, 'set progress')
    call expect(kin_set_progress(a, c_null_funptr, c_null_ptr) == KIN_OK, 'remove progress')
    call expect(kin_set_progress(c_null_ptr, c_null_funptr, c_null_ptr) == KIN_ENULL, 'NULL handle')
    call kin_homotopy_options_default(ho)
    call expect(ho%max_paths == KIN_HOMOTOPY_MAX_PATHS .and. ho%seed == 1 .and. &
                .not. c_associated(ho%progress), 'homotopy defaults')
    ho%progress = c_funloc(count_calls)
    ho%user = c_loc(calls)
    calls = 0
    call expect(kin_quadrics_homotopy_ex(2, ns, q, ho, betas, 2, nsol, mult, hi) == KIN_OK, &
                'homotopy with progress')
    call expect(nsol == 2 .and. hi%real_distinct == 2, 'two real solutions')
    call expect(calls >= 2, 'progress called at the start and at the end')
    calls = -1
    call expect(kin_quadrics_homotopy_ex(2, ns, q, ho, betas, 2, nsol, mult, hi) == KIN_ECANCELLED, &
                'a nonzero return cancels')
    call expect(nsol == 0, 'nothing found when cancelled')
    ho%max_paths = 1
    call expect(kin_quadrics_homotopy_ex(2, ns, q, ho, betas, 2, nsol, mult, hi) == KIN_ELIMIT, &
                'more paths than max_paths')
    call kin_assembly_free(a)
  end subroutine

  subroutine test_io()
    type(c_ptr) :: a, b
    real(c_double) :: x1(2, 4), x2(2, 4)
    character(len=:), allocatable :: text, text2, msg
    call expect(kin_model_threebar(KIN_THREEBAR_RC, a) == KIN_OK, 'three-bar')
    call expect(kinf_save_string(a, text, name='three-bar', errmsg=msg) == KIN_OK, 'save string')
    call expect(len(text) > 0 .and. len(msg) == 0, 'a model text, no message')
    call expect(kinf_load_string(text, b) == KIN_OK, 'load it back')
    call expect(kin_get_coords(a, x1) == KIN_OK, 'coords a')
    call expect(kin_get_coords(b, x2) == KIN_OK, 'coords b')
    call expect(all(x1 == x2) .and. kin_nbars(b) == 3, 'same model through the text')
    call kin_assembly_free(b)
    call expect(kinf_save(a, 'test_fortran_io.json  ', name='three-bar') == KIN_OK, 'save file')
    call expect(kinf_load('test_fortran_io.json', b) == KIN_OK, 'load file')
    call expect(kinf_save_string(b, text2) == KIN_OK, 'save the loaded one')
    call expect(kin_get_coords(b, x2) == KIN_OK .and. kin_nfree(b) == 4, 'loaded sizes')
    call expect(all(x1 == x2), 'same coordinates through the file')
    call kin_assembly_free(b)
    call expect(kinf_load('no/such/dir/model.json', b, errmsg=msg) == KIN_EIO, 'missing file')
    call expect(len(msg) > 0 .and. .not. c_associated(b), 'missing file: message, no handle')
    call expect(kinf_load_string('{"dim": 2, "joints": [', b, errmsg=msg) == KIN_EFORMAT, &
                'malformed text')
    call expect(len(msg) > 0, 'malformed text: message')
    call expect(kinf_save_string(c_null_ptr, text) == KIN_ENULL .and. len(text) == 0, 'NULL handle')
    call kin_assembly_free(a)
  end subroutine

end program test_fortran_api
