! libkin for Fortran: module libkin (Fortran 2003, iso_c_binding).
!
! Two layers, both public:
!  - the C API one to one: every function of include/libkin/*.h under its C
!    name, bind(C) with the C types; the four calls that return a C string
!    are bound as <name>_c (returning type(c_ptr)) and their C names are
!    Fortran functions returning a Fortran string (kin_strerror, ...);
!  - Fortran-friendly wrappers named kinf_*: shapes taken from the arrays,
!    logical supports, 1-based joint indices on request, messages as
!    Fortran strings, and array sizes checked before C writes into them.
! The named constants (status codes from the KIN_STATUS_LIST X-macro, the
! enums, the version) are generated from the C headers at build time
! (fortran/gen_constants.c) and included below. The conventions (joint-major
! coordinates = a Fortran array xyz(dim, njoints), column-major matrices,
! 0-based indices in the C layer) are those of kin_assembly.h; see
! docs/fortran.md.
module libkin
  use, intrinsic :: iso_c_binding
  implicit none
  private

  include 'libkin_constants.inc'

  ! ---- the public structs (kin_assembly.h, kin_path.h, kin_locate.h,
  ! kin_branch.h, kin_models.h); test_fortran_layout checks sizes and
  ! offsets. Each starts with `size` (docs/abi.md), initialised to the C
  ! sizeof of the headers this module was made from, so a declared variable
  ! is ready to pass; keep it when copying or resetting one.
  type, bind(C), public :: kin_analysis
    integer(c_size_t) :: size = KIN_SIZEOF_ANALYSIS
    integer(c_int) :: rank = 0, m = 0, m_rigid = 0, m_internal = 0, s = 0
    real(c_double) :: v_max = 0, v_r = 0
    integer(c_int) :: s_trivial = 0
  end type

  type, bind(C), public :: kin_options
    integer(c_size_t) :: size = KIN_SIZEOF_OPTIONS
    real(c_double) :: rank_tol = 0, corrector_tol = 0
    integer(c_int) :: corrector_max_iter = 0
    real(c_double) :: step_fraction = 0
    integer(c_int) :: max_halvings = 0
    real(c_double) :: direction_tol = 0, max_correction = 0
    integer(c_int) :: factorization = 0
    integer(c_int) :: step_control = 0
    real(c_double) :: coord_resolution = 0
  end type

  type, bind(C), public :: kin_step_info
    integer(c_size_t) :: size = KIN_SIZEOF_STEP_INFO
    real(c_double) :: l = 0, delta = 0, v_r = 0, residual = 0, cos_turn = 0
    integer(c_int) :: iterations = 0, halvings = 0, factorizations = 0, m_internal = 0
    real(c_double) :: strain_floor = 0, tol_used = 0
  end type

  type, bind(C), public :: kin_locate_options
    integer(c_size_t) :: size = KIN_SIZEOF_LOCATE_OPTIONS
    integer(c_int) :: method = 0
    real(c_double) :: vr_tol = 0, switch_eps = 0, delta = 0
    integer(c_int) :: max_steps = 0, max_iter = 0, use_switch_rule = 0
  end type

  type, bind(C), public :: kin_locate_info
    integer(c_size_t) :: size = KIN_SIZEOF_LOCATE_INFO
    integer(c_int) :: event = 0, located = 0, steps = 0, factorizations = 0, forward = 0
    real(c_double) :: v_r = 0, v_r_rel = 0, distance = 0
    integer(c_int) :: path_kept = 0, m_internal = 0, s = 0, zero_order = 0
    ! layout 2: a proven enclosure of v_r (valid when v_r_bounded = 1)
    real(c_double) :: v_r_lo = 0, v_r_hi = 0, v_r_rel_hi = 0
    integer(c_int) :: v_r_bounded = 0
    ! layout 3: a proven exactly singular configuration near the final point
    ! (valid when sing_proven = 1; docs/locate.md "Certified bifurcations")
    real(c_double) :: sing_distance = 0, sing_dlength = 0, sing_unique = 0
    integer(c_int) :: sing_proven = 0, sing_corank = 0
  end type

  type, bind(C), public :: kin_solve_info
    integer(c_size_t) :: size = KIN_SIZEOF_SOLVE_INFO
    integer(c_int) :: starts = 0, converged = 0, distinct = 0, gsl_errors = 0
    real(c_double) :: max_residual = 0
  end type

  type, bind(C), public :: kin_homotopy_info
    integer(c_size_t) :: size = KIN_SIZEOF_HOMOTOPY_INFO
    integer(c_int) :: paths = 0, real = 0, real_distinct = 0, nonreal = 0, singular = 0
    integer(c_int) :: failed = 0, uncertified = 0, retracked = 0, duplicates = 0, unpaired = 0
    integer(c_int) :: steps = 0, rejected = 0
    real(c_double) :: max_residual = 0, max_cond = 0
    ! layout 2: 64-bit step totals, records that failed the merge's check
    integer(c_long_long) :: steps_total = 0, rejected_total = 0
    integer(c_int) :: rechecks_failed = 0
    ! layout 3: the interval proofs (docs/branches.md "What certified means")
    integer(c_int) :: proven_real = 0, proven_nonreal = 0, unproven = 0, proven_all = 0
    integer(c_int) :: proven_refined = 0, proven_overlap = 0, unproven_nopoint = 0, unproven_refused = 0
  end type

  type, bind(C), public :: kin_homotopy_sym_info
    integer(c_size_t) :: size = KIN_SIZEOF_HOMOTOPY_SYM_INFO
    integer(c_int) :: group = 0, orbits = 0, found = 0, monodromy_paths = 0, final_paths = 0
    real(c_double) :: monodromy_steps = 0, monodromy_rejected = 0
  end type

  ! progress: c_funloc of a bind(C) function with the interface
  ! kin_progress_callback, or c_null_funptr; user is passed to it unchanged.
  ! Start from kin_homotopy_options_default.
  type, bind(C), public :: kin_homotopy_options
    integer(c_size_t) :: size = KIN_SIZEOF_HOMOTOPY_OPTIONS
    integer(c_long) :: seed = 0
    integer(c_int) :: nthreads = 0
    integer(c_long) :: max_paths = 0
    type(c_funptr) :: progress = c_null_funptr
    type(c_ptr) :: user = c_null_ptr
    ! layout 2: 2 prove every endpoint (exact integers and Arb only; the default),
    ! 1 a double-precision test with a priori bounds first, then those, 0 none
    integer(c_int) :: prove = 2
  end type

  type, bind(C), public :: kin_branch_path
    integer(c_size_t) :: size = KIN_SIZEOF_BRANCH_PATH
    integer(c_int) :: beta = 0, sign = 0, exists = 0, tangent_ok = 0, path_id = 0
    real(c_double) :: length = 0, tangent_cos = 0
  end type

  ! One record of the complete solver's shards (kin_branch.h): arrays of it
  ! have stride KIN_HOMOTOPY_ENDPOINT_SIZE.
  type, bind(C), public :: kin_homotopy_endpoint
    integer(c_size_t) :: size = KIN_SIZEOF_HOMOTOPY_ENDPOINT
    integer(c_int) :: path = 0, kind = 0, chart = 0, steps = 0, rejected = 0, recharts = 0
    integer(c_int) :: converged = 0, reserved = 0
    real(c_double) :: rminus = 0, rplus = 0, cond = 0, sigma = 0
  end type

  ! Start from kin_follow_options_default.
  type, bind(C), public :: kin_follow_options
    integer(c_size_t) :: size = KIN_SIZEOF_FOLLOW_OPTIONS
    real(c_double) :: vr_tol = 0, vr_floor = 0, switch_eps = 0, delta = 0
    integer(c_int) :: max_steps = 0, max_iter = 0
    real(c_double) :: max_length = 0, loop_tol = 0, first_step = 0, branch_cos = 0
    integer(c_int) :: steps_mode = 0
    real(c_double) :: branch_margin = 0
    type(c_funptr) :: return_fn = c_null_funptr
    type(c_ptr) :: return_user = c_null_ptr
    integer(c_int) :: return_own = 0
    integer(c_int) :: hold_hinges = 0
    real(c_double) :: hold_rate_tol = 0
  end type

  type, bind(C), public :: kin_follow_info
    integer(c_size_t) :: size = KIN_SIZEOF_FOLLOW_INFO
    integer(c_int) :: event = 0, status = 0, steps = 0, forward = 0, factorizations = 0
    integer(c_int) :: attempts = 0
    real(c_double) :: length = 0, vr_tol_used = 0, v_r_rel = 0
    integer(c_int) :: m_internal = 0, s = 0, zero_order = 0, path_kept = 0, at_start = 0
    real(c_double) :: start_distance = 0, tangent_cos = 0
    integer(c_int) :: cheap_steps = 0, handovers = 0, samples = 0, return_branch = 0
    real(c_double) :: return_angle = 0, return_gap = 0
    real(c_double) :: min_width = 0
    integer(c_int) :: min_located = 0, min_evals = 0
    integer(c_int) :: hinge = 0, held = 0, held_m = 0, reopened = 0
  end type

  ! widths: c_loc of a target array of n_loops reals, or c_null_ptr (the
  ! default widths); kinf_model_sail takes the array itself.
  type, bind(C), public :: kin_sail_params
    integer(c_size_t) :: size = KIN_SIZEOF_SAIL_PARAMS
    integer(c_int) :: n_sides = 0, n_loops = 0
    real(c_double) :: side = 0
    type(c_ptr) :: widths = c_null_ptr
    integer(c_int) :: support = 0, diagonal = 0
  end type

  ! ---- the C API (contracts: the C headers) -----------------------------
  public :: kin_version_number, kin_version_string_c, kin_strerror_c, kin_status_name_c
  public :: kin_assembly_create, kin_assembly_clone, kin_assembly_free, kin_last_error_c
  public :: kin_dim, kin_njoints, kin_nbars, kin_nfree, kin_free_index
  public :: kin_get_bars, kin_get_rest_lengths, kin_get_fixed, kin_get_coords, kin_set_coords
  public :: kin_get_lengths, kin_max_strain, kin_get_equilibrium_matrix
  public :: kin_analyse, kin_get_analysis, kin_get_analysis_route, kin_get_singular_values, kin_get_mechanisms
  public :: kin_get_self_stresses
  public :: kin_options_default, kin_options_default_c, kin_options_init, kin_set_options, kin_get_options, kin_step
  public :: kin_path_set_direction, kin_get_tangent, kin_path_length, kin_path_reset, kin_relax
  public :: kin_locate_options_default, kin_locate_options_default_c, kin_locate_options_init
  public :: kin_test_function, kin_locate_next, kin_prove_singular
  public :: kin_second_order, kin_quadrics_scan, kin_quadrics_homotopy, kin_branch_paths
  public :: kin_homotopy_options_default, kin_homotopy_options_default_c, kin_homotopy_options_init
  public :: kin_quadrics_homotopy_ex
  public :: kin_quadrics_homotopy_range, kin_quadrics_homotopy_merge, kin_quadrics_homotopy_sym
  public :: kin_quadrics_homotopy_merge_equivariant
  public :: kin_quadrics_equivariant_form, kin_quadrics_homotopy_orbit_range
  public :: kin_follow_options_default, kin_follow_options_default_c, kin_follow_options_init
  public :: kin_follow_event, kin_follow_event_ex
  public :: kin_set_progress, kin_progress_callback
  public :: kin_assembly_load, kin_assembly_load_limited, kin_assembly_load_string, kin_assembly_save
  public :: kin_assembly_save_string, kin_free_string
  public :: kin_model_threebar, kin_sail_params_default, kin_sail_params_default_c, kin_sail_params_init
  public :: kin_sail_size, kin_model_sail
  public :: kin_symmetries, kin_mechanism_group
  public :: kin_set_panels, kin_npanels, kin_get_panels, kin_set_thickness, kin_get_thickness
  public :: kin_has_contact_model, kin_clearance, kin_set_contact_events, kin_last_contact
  public :: kin_set_device_bars, kin_get_device_bars, kin_set_hinge_contact, kin_get_hinge_contact
  public :: kin_nhinges, kin_get_hinges, kin_hinge_angles, kin_hinge_sides
  ! ---- Fortran strings and wrappers --------------------------------------
  public :: kin_version_string, kin_strerror, kin_status_name, kin_last_error
  public :: kinf_create, kinf_get_bars, kinf_get_fixed, kinf_free_index, kinf_model_sail
  public :: kinf_load, kinf_load_string, kinf_save, kinf_save_string

  interface
    ! kin_version.h
    function kin_version_number() bind(C, name='kin_version_number')
      import :: c_int
      integer(c_int) :: kin_version_number
    end function
    function kin_version_string_c() bind(C, name='kin_version_string')
      import :: c_ptr
      type(c_ptr) :: kin_version_string_c
    end function

    ! kin_status.h
    function kin_strerror_c(status) bind(C, name='kin_strerror')
      import :: c_int, c_ptr
      integer(c_int), value :: status
      type(c_ptr) :: kin_strerror_c
    end function
    function kin_status_name_c(status) bind(C, name='kin_status_name')
      import :: c_int, c_ptr
      integer(c_int), value :: status
      type(c_ptr) :: kin_status_name_c
    end function

    ! kin_assembly.h. fixed, rest_lengths and errbuf may be c_null_ptr;
    ! otherwise c_loc of an integer(c_signed_char) array (fixed), a real
    ! array (rest_lengths) or a character(kind=c_char) buffer of errlen.
    function kin_assembly_create(dim, njoints, xyz, fixed, nbars, bars, rest_lengths, out, &
                                 errbuf, errlen) bind(C, name='kin_assembly_create')
      import :: c_int, c_double, c_ptr, c_size_t
      integer(c_int), value :: dim, njoints, nbars
      real(c_double), intent(in) :: xyz(*)
      type(c_ptr), value :: fixed, rest_lengths, errbuf
      integer(c_int), intent(in) :: bars(*)
      type(c_ptr), intent(out) :: out
      integer(c_size_t), value :: errlen
      integer(c_int) :: kin_assembly_create
    end function
    function kin_assembly_clone(a, out) bind(C, name='kin_assembly_clone')
      import :: c_int, c_ptr
      type(c_ptr), value :: a
      type(c_ptr), intent(out) :: out
      integer(c_int) :: kin_assembly_clone
    end function
    subroutine kin_assembly_free(a) bind(C, name='kin_assembly_free')
      import :: c_ptr
      type(c_ptr), value :: a
    end subroutine
    function kin_last_error_c(a) bind(C, name='kin_last_error')
      import :: c_ptr
      type(c_ptr), value :: a
      type(c_ptr) :: kin_last_error_c
    end function
    function kin_dim(a) bind(C, name='kin_dim')
      import :: c_int, c_ptr
      type(c_ptr), value :: a
      integer(c_int) :: kin_dim
    end function
    function kin_njoints(a) bind(C, name='kin_njoints')
      import :: c_int, c_ptr
      type(c_ptr), value :: a
      integer(c_int) :: kin_njoints
    end function
    function kin_nbars(a) bind(C, name='kin_nbars')
      import :: c_int, c_ptr
      type(c_ptr), value :: a
      integer(c_int) :: kin_nbars
    end function
    function kin_nfree(a) bind(C, name='kin_nfree')
      import :: c_int, c_ptr
      type(c_ptr), value :: a
      integer(c_int) :: kin_nfree
    end function
    function kin_free_index(a, joint, axis) bind(C, name='kin_free_index')
      import :: c_int, c_ptr
      type(c_ptr), value :: a
      integer(c_int), value :: joint, axis
      integer(c_int) :: kin_free_index
    end function
    function kin_get_bars(a, bars) bind(C, name='kin_get_bars')
      import :: c_int, c_ptr
      type(c_ptr), value :: a
      integer(c_int), intent(out) :: bars(*)
      integer(c_int) :: kin_get_bars
    end function
    function kin_get_rest_lengths(a, lengths) bind(C, name='kin_get_rest_lengths')
      import :: c_int, c_double, c_ptr
      type(c_ptr), value :: a
      real(c_double), intent(out) :: lengths(*)
      integer(c_int) :: kin_get_rest_lengths
    end function
    function kin_get_fixed(a, fixed) bind(C, name='kin_get_fixed')
      import :: c_int, c_ptr, c_signed_char
      type(c_ptr), value :: a
      integer(c_signed_char), intent(out) :: fixed(*)
      integer(c_int) :: kin_get_fixed
    end function
    function kin_get_coords(a, xyz) bind(C, name='kin_get_coords')
      import :: c_int, c_double, c_ptr
      type(c_ptr), value :: a
      real(c_double), intent(out) :: xyz(*)
      integer(c_int) :: kin_get_coords
    end function
    function kin_set_coords(a, xyz) bind(C, name='kin_set_coords')
      import :: c_int, c_double, c_ptr
      type(c_ptr), value :: a
      real(c_double), intent(in) :: xyz(*)
      integer(c_int) :: kin_set_coords
    end function
    function kin_get_lengths(a, lengths) bind(C, name='kin_get_lengths')
      import :: c_int, c_double, c_ptr
      type(c_ptr), value :: a
      real(c_double), intent(out) :: lengths(*)
      integer(c_int) :: kin_get_lengths
    end function
    function kin_max_strain(a) bind(C, name='kin_max_strain')
      import :: c_double, c_ptr
      type(c_ptr), value :: a
      real(c_double) :: kin_max_strain
    end function
    function kin_get_equilibrium_matrix(a, h, ldh) bind(C, name='kin_get_equilibrium_matrix')
      import :: c_int, c_double, c_ptr
      type(c_ptr), value :: a
      real(c_double), intent(out) :: h(*)
      integer(c_int), value :: ldh
      integer(c_int) :: kin_get_equilibrium_matrix
    end function
    function kin_analyse(a, out) bind(C, name='kin_analyse')
      import :: c_int, c_ptr, kin_analysis
      type(c_ptr), value :: a
      type(kin_analysis), intent(out) :: out
      integer(c_int) :: kin_analyse
    end function
    function kin_get_analysis(a, out) bind(C, name='kin_get_analysis')
      import :: c_int, c_ptr, kin_analysis
      type(c_ptr), value :: a
      type(kin_analysis), intent(out) :: out
      integer(c_int) :: kin_get_analysis
    end function
    function kin_get_singular_values(a, sv, n) bind(C, name='kin_get_singular_values')
      import :: c_int, c_double, c_ptr
      type(c_ptr), value :: a
      real(c_double), intent(out) :: sv(*)
      integer(c_int), value :: n
      integer(c_int) :: kin_get_singular_values
    end function
    function kin_get_mechanisms(a, kind, u, ldu, cols) bind(C, name='kin_get_mechanisms')
      import :: c_int, c_double, c_ptr
      type(c_ptr), value :: a
      integer(c_int), value :: kind, ldu, cols
      real(c_double), intent(inout) :: u(*)
      integer(c_int) :: kin_get_mechanisms
    end function
    function kin_get_self_stresses(a, w, ldw, cols) bind(C, name='kin_get_self_stresses')
      import :: c_int, c_double, c_ptr
      type(c_ptr), value :: a
      real(c_double), intent(inout) :: w(*)
      integer(c_int), value :: ldw, cols
      integer(c_int) :: kin_get_self_stresses
    end function

    ! kin_path.h
    ! the plain symbol fills only the first layout (docs/abi.md); the
    ! module's kin_options_default calls kin_options_init with the whole size
    subroutine kin_options_default_c(o) bind(C, name='kin_options_default')
      import :: kin_options
      type(kin_options), intent(out) :: o
    end subroutine
    function kin_options_init(o, size) bind(C, name='kin_options_init')
      import :: c_int, c_size_t, kin_options
      type(kin_options), intent(out) :: o
      integer(c_size_t), value :: size
      integer(c_int) :: kin_options_init
    end function
    function kin_set_options(a, o) bind(C, name='kin_set_options')
      import :: c_int, c_ptr, kin_options
      type(c_ptr), value :: a
      type(kin_options), intent(in) :: o
      integer(c_int) :: kin_set_options
    end function
    function kin_get_options(a, o) bind(C, name='kin_get_options')
      import :: c_int, c_ptr, kin_options
      type(c_ptr), value :: a
      type(kin_options), intent(out) :: o
      integer(c_int) :: kin_get_options
    end function
    function kin_step(a, delta, info) bind(C, name='kin_step')
      import :: c_int, c_double, c_ptr, kin_step_info
      type(c_ptr), value :: a
      real(c_double), value :: delta
      type(kin_step_info), intent(out) :: info
      integer(c_int) :: kin_step
    end function
    function kin_path_set_direction(a, dir, n) bind(C, name='kin_path_set_direction')
      import :: c_int, c_double, c_ptr
      type(c_ptr), value :: a
      real(c_double), intent(in) :: dir(*)
      integer(c_int), value :: n
      integer(c_int) :: kin_path_set_direction
    end function
    function kin_get_tangent(a, t, n) bind(C, name='kin_get_tangent')
      import :: c_int, c_double, c_ptr
      type(c_ptr), value :: a
      real(c_double), intent(out) :: t(*)
      integer(c_int), value :: n
      integer(c_int) :: kin_get_tangent
    end function
    function kin_path_length(a) bind(C, name='kin_path_length')
      import :: c_double, c_ptr
      type(c_ptr), value :: a
      real(c_double) :: kin_path_length
    end function
    function kin_path_reset(a) bind(C, name='kin_path_reset')
      import :: c_int, c_ptr
      type(c_ptr), value :: a
      integer(c_int) :: kin_path_reset
    end function
    function kin_relax(a, max_iter, residual) bind(C, name='kin_relax')
      import :: c_int, c_double, c_ptr
      type(c_ptr), value :: a
      integer(c_int), value :: max_iter
      real(c_double), intent(out) :: residual
      integer(c_int) :: kin_relax
    end function

    ! kin_locate.h
    ! the plain symbol fills only the first layout (docs/abi.md); the
    ! module's kin_locate_options_default calls kin_locate_options_init with the whole size
    subroutine kin_locate_options_default_c(o) bind(C, name='kin_locate_options_default')
      import :: kin_locate_options
      type(kin_locate_options), intent(out) :: o
    end subroutine
    function kin_locate_options_init(o, size) bind(C, name='kin_locate_options_init')
      import :: c_int, c_size_t, kin_locate_options
      type(kin_locate_options), intent(out) :: o
      integer(c_size_t), value :: size
      integer(c_int) :: kin_locate_options_init
    end function
    function kin_test_function(a, tau) bind(C, name='kin_test_function')
      import :: c_int, c_double, c_ptr
      type(c_ptr), value :: a
      real(c_double), intent(out) :: tau
      integer(c_int) :: kin_test_function
    end function
    function kin_locate_next(a, o, info) bind(C, name='kin_locate_next')
      import :: c_int, c_ptr, kin_locate_options, kin_locate_info
      type(c_ptr), value :: a
      type(kin_locate_options), intent(in) :: o
      type(kin_locate_info), intent(out) :: info
      integer(c_int) :: kin_locate_next
    end function
    function kin_prove_singular(a, info) bind(C, name='kin_prove_singular')
      import :: c_int, c_ptr, kin_locate_info
      type(c_ptr), value :: a
      type(kin_locate_info), intent(inout) :: info
      integer(c_int) :: kin_prove_singular
    end function

    ! kin_branch.h (seed: the bits of a C unsigned long)
    function kin_second_order(a, weighting, normalise, q, nq, s_out) bind(C, name='kin_second_order')
      import :: c_int, c_double, c_ptr
      type(c_ptr), value :: a
      integer(c_int), value :: weighting, normalise, nq
      real(c_double), intent(out) :: q(*)
      integer(c_int), intent(out) :: s_out
      integer(c_int) :: kin_second_order
    end function
    function kin_quadrics_scan(m, s, q, starts, seed, betas, maxsol, nsol, info) &
        bind(C, name='kin_quadrics_scan')
      import :: c_int, c_double, c_long, kin_solve_info
      integer(c_int), value :: m, s, starts, maxsol
      real(c_double), intent(in) :: q(*)
      integer(c_long), value :: seed
      real(c_double), intent(out) :: betas(*)
      integer(c_int), intent(out) :: nsol
      type(kin_solve_info), intent(out) :: info
      integer(c_int) :: kin_quadrics_scan
    end function
    function kin_quadrics_homotopy(m, s, q, seed, nthreads, betas, maxsol, nsol, multiplicity, &
                                   info) bind(C, name='kin_quadrics_homotopy')
      import :: c_int, c_double, c_long, kin_homotopy_info
      integer(c_int), value :: m, s, nthreads, maxsol
      real(c_double), intent(in) :: q(*)
      integer(c_long), value :: seed
      real(c_double), intent(out) :: betas(*)
      integer(c_int), intent(out) :: nsol
      integer(c_int), intent(out) :: multiplicity(*)
      type(kin_homotopy_info), intent(out) :: info
      integer(c_int) :: kin_quadrics_homotopy
    end function
    ! final_xyz: c_loc of a real array of njoints*dim*2*nbeta, or c_null_ptr
    function kin_branch_paths(a, betas, nbeta, l_target, paths, final_xyz, ndistinct) &
        bind(C, name='kin_branch_paths')
      import :: c_int, c_double, c_ptr, kin_branch_path
      type(c_ptr), value :: a
      real(c_double), intent(in) :: betas(*)
      integer(c_int), value :: nbeta
      real(c_double), value :: l_target
      type(kin_branch_path), intent(inout) :: paths(*)
      type(c_ptr), value :: final_xyz
      integer(c_int), intent(out) :: ndistinct
      integer(c_int) :: kin_branch_paths
    end function

    ! the plain symbol fills only the first layout (docs/abi.md); the
    ! module's kin_homotopy_options_default calls kin_homotopy_options_init with the whole size
    subroutine kin_homotopy_options_default_c(o) bind(C, name='kin_homotopy_options_default')
      import :: kin_homotopy_options
      type(kin_homotopy_options), intent(out) :: o
    end subroutine
    function kin_homotopy_options_init(o, size) bind(C, name='kin_homotopy_options_init')
      import :: c_int, c_size_t, kin_homotopy_options
      type(kin_homotopy_options), intent(out) :: o
      integer(c_size_t), value :: size
      integer(c_int) :: kin_homotopy_options_init
    end function
    function kin_quadrics_homotopy_ex(m, s, q, opt, betas, maxsol, nsol, multiplicity, info) &
        bind(C, name='kin_quadrics_homotopy_ex')
      import :: c_int, c_double, kin_homotopy_options, kin_homotopy_info
      integer(c_int), value :: m, s, maxsol
      real(c_double), intent(in) :: q(*)
      type(kin_homotopy_options), intent(in) :: opt
      real(c_double), intent(out) :: betas(*)
      integer(c_int), intent(out) :: nsol
      integer(c_int), intent(out) :: multiplicity(*)
      type(kin_homotopy_info), intent(out) :: info
      integer(c_int) :: kin_quadrics_homotopy_ex
    end function
    ! r: ngroup m x m matrices (column-major); sinfo: c_loc of a
    ! kin_homotopy_sym_info or c_null_ptr; err: a character(len=errlen)
    ! buffer (c_loc of its first character) or c_null_ptr
    function kin_quadrics_homotopy_sym(m, s, q, ngroup, r, opt, betas, maxsol, nsol, multiplicity, info, &
        sinfo, err, errlen) bind(C, name='kin_quadrics_homotopy_sym')
      import :: c_int, c_double, c_ptr, c_size_t, kin_homotopy_options, kin_homotopy_info
      integer(c_int), value :: m, s, ngroup, maxsol
      real(c_double), intent(in) :: q(*), r(*)
      type(kin_homotopy_options), intent(in) :: opt
      real(c_double), intent(out) :: betas(*)
      integer(c_int), intent(out) :: nsol
      integer(c_int), intent(out) :: multiplicity(*)
      type(kin_homotopy_info), intent(out) :: info
      type(c_ptr), value :: sinfo, err
      integer(c_size_t), value :: errlen
      integer(c_int) :: kin_quadrics_homotopy_sym
    end function
    ! ends: element 1's size must be KIN_SIZEOF_HOMOTOPY_ENDPOINT (the default)
    function kin_quadrics_homotopy_range(m, s, q, opt, first_path, npaths, ends, z) &
        bind(C, name='kin_quadrics_homotopy_range')
      import :: c_int, c_long, c_double, kin_homotopy_options, kin_homotopy_endpoint
      integer(c_int), value :: m, s
      real(c_double), intent(in) :: q(*)
      type(kin_homotopy_options), intent(in) :: opt
      integer(c_long), value :: first_path, npaths
      type(kin_homotopy_endpoint), intent(inout) :: ends(*)
      real(c_double), intent(out) :: z(*)
      integer(c_int) :: kin_quadrics_homotopy_range
    end function
    ! err: c_loc of a character(len=errlen) buffer or c_null_ptr
    function kin_quadrics_equivariant_form(m, s, q, ngroup, r, seed, qt, u, perm, order, norbits, err, &
        errlen) bind(C, name='kin_quadrics_equivariant_form')
      import :: c_int, c_long, c_double, c_ptr, c_size_t
      integer(c_int), value :: m, s, ngroup
      real(c_double), intent(in) :: q(*), r(*)
      integer(c_long), value :: seed
      real(c_double), intent(out) :: qt(*), u(*)
      integer(c_int), intent(out) :: perm(*), order
      integer(c_long), intent(out) :: norbits
      type(c_ptr), value :: err
      integer(c_size_t), value :: errlen
      integer(c_int) :: kin_quadrics_equivariant_form
    end function
    ! ends: element 1's size must be KIN_SIZEOF_HOMOTOPY_ENDPOINT (the default)
    function kin_quadrics_homotopy_orbit_range(m, s, qt, perm, opt, first_orbit, norbits, maxends, ends, z, &
        nends) bind(C, name='kin_quadrics_homotopy_orbit_range')
      import :: c_int, c_long, c_double, kin_homotopy_options, kin_homotopy_endpoint
      integer(c_int), value :: m, s
      real(c_double), intent(in) :: qt(*)
      integer(c_int), intent(in) :: perm(*)
      type(kin_homotopy_options), intent(in) :: opt
      integer(c_long), value :: first_orbit, norbits, maxends
      type(kin_homotopy_endpoint), intent(inout) :: ends(*)
      real(c_double), intent(out) :: z(*)
      integer(c_long), intent(out) :: nends
      integer(c_int) :: kin_quadrics_homotopy_orbit_range
    end function
    function kin_quadrics_homotopy_merge(m, s, q, opt, ends, z, betas, maxsol, nsol, multiplicity, info) &
        bind(C, name='kin_quadrics_homotopy_merge')
      import :: c_int, c_double, kin_homotopy_options, kin_homotopy_endpoint, kin_homotopy_info
      integer(c_int), value :: m, s, maxsol
      real(c_double), intent(in) :: q(*)
      type(kin_homotopy_options), intent(in) :: opt
      type(kin_homotopy_endpoint), intent(in) :: ends(*)
      real(c_double), intent(in) :: z(*)
      real(c_double), intent(out) :: betas(*)
      integer(c_int), intent(out) :: nsol
      integer(c_int), intent(out) :: multiplicity(*)
      type(kin_homotopy_info), intent(out) :: info
      integer(c_int) :: kin_quadrics_homotopy_merge
    end function
    ! the proofs about q itself at beta = u x (qt, u: kin_quadrics_equivariant_form's)
    function kin_quadrics_homotopy_merge_equivariant(m, s, q, qt, u, opt, ends, z, betas, maxsol, nsol, &
        multiplicity, info) bind(C, name='kin_quadrics_homotopy_merge_equivariant')
      import :: c_int, c_double, kin_homotopy_options, kin_homotopy_endpoint, kin_homotopy_info
      integer(c_int), value :: m, s, maxsol
      real(c_double), intent(in) :: q(*), qt(*), u(*)
      type(kin_homotopy_options), intent(in) :: opt
      type(kin_homotopy_endpoint), intent(in) :: ends(*)
      real(c_double), intent(in) :: z(*)
      real(c_double), intent(out) :: betas(*)
      integer(c_int), intent(out) :: nsol
      integer(c_int), intent(out) :: multiplicity(*)
      type(kin_homotopy_info), intent(out) :: info
      integer(c_int) :: kin_quadrics_homotopy_merge_equivariant
    end function

    ! kin_follow.h. dir: c_loc of a real array of nfree, or c_null_ptr
    ! the plain symbol fills only the first layout (docs/abi.md); the
    ! module's kin_follow_options_default calls kin_follow_options_init with the whole size
    subroutine kin_follow_options_default_c(o) bind(C, name='kin_follow_options_default')
      import :: kin_follow_options
      type(kin_follow_options), intent(out) :: o
    end subroutine
    function kin_follow_options_init(o, size) bind(C, name='kin_follow_options_init')
      import :: c_int, c_size_t, kin_follow_options
      type(kin_follow_options), intent(out) :: o
      integer(c_size_t), value :: size
      integer(c_int) :: kin_follow_options_init
    end function
    function kin_follow_event(a, dir, o, info) bind(C, name='kin_follow_event')
      import :: c_int, c_ptr, kin_follow_options, kin_follow_info
      type(c_ptr), value :: a, dir
      type(kin_follow_options), intent(in) :: o
      type(kin_follow_info), intent(out) :: info
      integer(c_int) :: kin_follow_event
    end function

    ! kin_follow.h. branches, samples, sample_length, nsamples: c_loc of
    ! target arrays, or c_null_ptr
    function kin_follow_event_ex(a, dir, o, branches, nbranch, samples, sample_length, capacity, nsamples, info) &
        bind(C, name='kin_follow_event_ex')
      import :: c_int, c_ptr, kin_follow_options, kin_follow_info
      type(c_ptr), value :: a, dir, branches, samples, sample_length, nsamples
      integer(c_int), value :: nbranch, capacity
      type(kin_follow_options), intent(in) :: o
      type(kin_follow_info), intent(out) :: info
      integer(c_int) :: kin_follow_event_ex
    end function

    ! kin_progress.h. fn: c_funloc of a function with the interface
    ! kin_progress_callback (below), or c_null_funptr to remove it.
    function kin_set_progress(a, fn, user) bind(C, name='kin_set_progress')
      import :: c_int, c_ptr, c_funptr
      type(c_ptr), value :: a
      type(c_funptr), value :: fn
      type(c_ptr), value :: user
      integer(c_int) :: kin_set_progress
    end function

    ! kin_io.h. path: NUL-terminated (trim(path)//c_null_char), or use
    ! kinf_load / kinf_save; text of load_string: any character string with
    ! its length; name: c_null_ptr or c_loc of a NUL-terminated
    ! character(kind=c_char) array; errbuf as for kin_assembly_create.
    function kin_assembly_load(path, out, errbuf, errlen) bind(C, name='kin_assembly_load')
      import :: c_int, c_char, c_ptr, c_size_t
      character(kind=c_char), intent(in) :: path(*)
      type(c_ptr), intent(out) :: out
      type(c_ptr), value :: errbuf
      integer(c_size_t), value :: errlen
      integer(c_int) :: kin_assembly_load
    end function
    function kin_assembly_load_limited(path, max_bytes, out, errbuf, errlen) &
        bind(C, name='kin_assembly_load_limited')
      import :: c_int, c_char, c_ptr, c_size_t
      character(kind=c_char), intent(in) :: path(*)
      integer(c_size_t), value :: max_bytes
      type(c_ptr), intent(out) :: out
      type(c_ptr), value :: errbuf
      integer(c_size_t), value :: errlen
      integer(c_int) :: kin_assembly_load_limited
    end function
    function kin_assembly_load_string(text, len, out, errbuf, errlen) &
        bind(C, name='kin_assembly_load_string')
      import :: c_int, c_char, c_ptr, c_size_t
      character(kind=c_char), intent(in) :: text(*)
      integer(c_size_t), value :: len
      type(c_ptr), intent(out) :: out
      type(c_ptr), value :: errbuf
      integer(c_size_t), value :: errlen
      integer(c_int) :: kin_assembly_load_string
    end function
    function kin_assembly_save(a, name, path, errbuf, errlen) bind(C, name='kin_assembly_save')
      import :: c_int, c_char, c_ptr, c_size_t
      type(c_ptr), value :: a, name
      character(kind=c_char), intent(in) :: path(*)
      type(c_ptr), value :: errbuf
      integer(c_size_t), value :: errlen
      integer(c_int) :: kin_assembly_save
    end function
    ! text receives a C string to release with kin_free_string
    function kin_assembly_save_string(a, name, text, len, errbuf, errlen) &
        bind(C, name='kin_assembly_save_string')
      import :: c_int, c_ptr, c_size_t
      type(c_ptr), value :: a, name
      type(c_ptr), intent(out) :: text
      integer(c_size_t), intent(out) :: len
      type(c_ptr), value :: errbuf
      integer(c_size_t), value :: errlen
      integer(c_int) :: kin_assembly_save_string
    end function
    subroutine kin_free_string(text) bind(C, name='kin_free_string')
      import :: c_ptr
      type(c_ptr), value :: text
    end subroutine

    ! kin_symmetry.h. perm holds 0-based joint indices (perm(k*njoints + i + 1)
    ! is the image of joint i, 0-based, under symmetry k); KIN_ERANGE sets
    ! nsym / ngroup to the count needed
    function kin_symmetries(a, max_sym, perm, q, t, nsym) bind(C, name='kin_symmetries')
      import :: c_int, c_double, c_ptr
      type(c_ptr), value :: a
      integer(c_int), value :: max_sym
      integer(c_int), intent(inout) :: perm(*)
      real(c_double), intent(inout) :: q(*), t(*)
      integer(c_int), intent(out) :: nsym
      integer(c_int) :: kin_symmetries
    end function
    function kin_mechanism_group(a, max_group, r, ngroup) bind(C, name='kin_mechanism_group')
      import :: c_int, c_double, c_ptr
      type(c_ptr), value :: a
      integer(c_int), value :: max_group
      real(c_double), intent(inout) :: r(*)
      integer(c_int), intent(out) :: ngroup
      integer(c_int) :: kin_mechanism_group
    end function

    ! kin_models.h
    function kin_model_threebar(state, out) bind(C, name='kin_model_threebar')
      import :: c_int, c_ptr
      integer(c_int), value :: state
      type(c_ptr), intent(out) :: out
      integer(c_int) :: kin_model_threebar
    end function
    ! the plain symbol fills only the first layout (docs/abi.md); the
    ! module's kin_sail_params_default calls kin_sail_params_init
    subroutine kin_sail_params_default_c(p, n_sides, n_loops) bind(C, name='kin_sail_params_default')
      import :: c_int, kin_sail_params
      type(kin_sail_params), intent(out) :: p
      integer(c_int), value :: n_sides, n_loops
    end subroutine
    function kin_sail_params_init(p, size, n_sides, n_loops) bind(C, name='kin_sail_params_init')
      import :: c_int, c_size_t, kin_sail_params
      type(kin_sail_params), intent(out) :: p
      integer(c_size_t), value :: size
      integer(c_int), value :: n_sides, n_loops
      integer(c_int) :: kin_sail_params_init
    end function
    function kin_sail_size(p, njoints, nbars) bind(C, name='kin_sail_size')
      import :: c_int, kin_sail_params
      type(kin_sail_params), intent(in) :: p
      integer(c_int), intent(out) :: njoints, nbars
      integer(c_int) :: kin_sail_size
    end function
    function kin_model_sail(p, out, errbuf, errlen) bind(C, name='kin_model_sail')
      import :: c_int, c_ptr, c_size_t, kin_sail_params
      type(kin_sail_params), intent(in) :: p
      type(c_ptr), intent(out) :: out
      type(c_ptr), value :: errbuf
      integer(c_size_t), value :: errlen
      integer(c_int) :: kin_model_sail
    end function

    ! the C library's strlen, to read the strings above
    function c_strlen(s) bind(C, name='strlen')
      import :: c_ptr, c_size_t
      type(c_ptr), value :: s
      integer(c_size_t) :: c_strlen
    end function
    ! kin_contact.h: panels, thickness, clearance (docs/contact.md)
    function kin_set_panels(a, npanels, offsets, joints) bind(C, name='kin_set_panels')
      import :: c_int, c_ptr
      type(c_ptr), value :: a
      integer(c_int), value :: npanels
      integer(c_int), intent(in) :: offsets(*), joints(*)
      integer(c_int) :: kin_set_panels
    end function
    function kin_npanels(a) bind(C, name='kin_npanels')
      import :: c_int, c_ptr
      type(c_ptr), value :: a
      integer(c_int) :: kin_npanels
    end function
    function kin_get_panels(a, offsets, joints) bind(C, name='kin_get_panels')
      import :: c_int, c_ptr
      type(c_ptr), value :: a
      integer(c_int), intent(out) :: offsets(*), joints(*)
      integer(c_int) :: kin_get_panels
    end function
    function kin_set_thickness(a, t_default, bar_radius, panel_thickness) bind(C, name='kin_set_thickness')
      import :: c_int, c_double, c_ptr
      type(c_ptr), value :: a
      real(c_double), value :: t_default
      type(c_ptr), value :: bar_radius, panel_thickness
      integer(c_int) :: kin_set_thickness
    end function
    function kin_get_thickness(a, t_default, bar_radius, panel_thickness) bind(C, name='kin_get_thickness')
      import :: c_int, c_double, c_ptr
      type(c_ptr), value :: a
      real(c_double), intent(out) :: t_default
      type(c_ptr), value :: bar_radius, panel_thickness
      integer(c_int) :: kin_get_thickness
    end function
    function kin_has_contact_model(a) bind(C, name='kin_has_contact_model')
      import :: c_int, c_ptr
      type(c_ptr), value :: a
      integer(c_int) :: kin_has_contact_model
    end function
    function kin_clearance(a, xyz, cutoff, clearance, parts, points) bind(C, name='kin_clearance')
      import :: c_int, c_double, c_ptr
      type(c_ptr), value :: a, xyz
      real(c_double), value :: cutoff
      real(c_double), intent(out) :: clearance
      integer(c_int), intent(out) :: parts(4)
      real(c_double), intent(out) :: points(*)
      integer(c_int) :: kin_clearance
    end function
    function kin_set_contact_events(a, on, tol) bind(C, name='kin_set_contact_events')
      import :: c_int, c_double, c_ptr
      type(c_ptr), value :: a
      integer(c_int), value :: on
      real(c_double), value :: tol
      integer(c_int) :: kin_set_contact_events
    end function
    function kin_last_contact(a, clearance, parts, points, bracket) bind(C, name='kin_last_contact')
      import :: c_int, c_double, c_ptr
      type(c_ptr), value :: a
      real(c_double), intent(out) :: clearance, bracket
      integer(c_int), intent(out) :: parts(4)
      real(c_double), intent(out) :: points(*)
      integer(c_int) :: kin_last_contact
    end function
    function kin_get_analysis_route(a, route) bind(C, name='kin_get_analysis_route')
      import :: c_int, c_ptr
      type(c_ptr), value :: a
      integer(c_int), intent(out) :: route
      integer(c_int) :: kin_get_analysis_route
    end function
    function kin_set_device_bars(a, ndev, bars) bind(C, name='kin_set_device_bars')
      import :: c_int, c_ptr
      type(c_ptr), value :: a
      integer(c_int), value :: ndev
      integer(c_int), intent(in) :: bars(*)
      integer(c_int) :: kin_set_device_bars
    end function
    function kin_get_device_bars(a, ndev, bars) bind(C, name='kin_get_device_bars')
      import :: c_int, c_ptr
      type(c_ptr), value :: a
      integer(c_int), intent(out) :: ndev
      integer(c_int), intent(out) :: bars(*)
      integer(c_int) :: kin_get_device_bars
    end function
    function kin_set_hinge_contact(a, on) bind(C, name='kin_set_hinge_contact')
      import :: c_int, c_ptr
      type(c_ptr), value :: a
      integer(c_int), value :: on
      integer(c_int) :: kin_set_hinge_contact
    end function
    function kin_get_hinge_contact(a) bind(C, name='kin_get_hinge_contact')
      import :: c_int, c_ptr
      type(c_ptr), value :: a
      integer(c_int) :: kin_get_hinge_contact
    end function
    function kin_nhinges(a) bind(C, name='kin_nhinges')
      import :: c_int, c_ptr
      type(c_ptr), value :: a
      integer(c_int) :: kin_nhinges
    end function
    function kin_get_hinges(a, joints, panels) bind(C, name='kin_get_hinges')
      import :: c_int, c_ptr
      type(c_ptr), value :: a
      integer(c_int), intent(out) :: joints(*), panels(*)
      integer(c_int) :: kin_get_hinges
    end function
    function kin_hinge_angles(a, xyz, fold) bind(C, name='kin_hinge_angles')
      import :: c_int, c_double, c_ptr
      type(c_ptr), value :: a, xyz
      real(c_double), intent(out) :: fold(*)
      integer(c_int) :: kin_hinge_angles
    end function
    function kin_hinge_sides(a, sides) bind(C, name='kin_hinge_sides')
      import :: c_int, c_ptr
      type(c_ptr), value :: a
      integer(c_int), intent(out) :: sides(*)
      integer(c_int) :: kin_hinge_sides
    end function
  end interface

  ! What a progress callback (kin_progress_fn) looks like in Fortran: write
  !   integer(c_int) function my_progress(user, done, total) bind(C)
  ! with these arguments and pass c_funloc(my_progress). Nonzero cancels.
  abstract interface
    function kin_progress_callback(user, done, total) bind(C)
      import :: c_int, c_double, c_ptr
      type(c_ptr), value :: user
      real(c_double), value :: done, total
      integer(c_int) :: kin_progress_callback
    end function
  end interface

  ! room for the errbuf messages of kinf_create / kinf_model_sail
  integer, parameter :: errbuf_len = 1024

contains

  ! The defaults of every field of the struct this module declares: the
  ! sized C form with the C sizeof of these headers (the plain C symbol,
  ! bound as *_default_c, fills only the first layout; docs/abi.md).
  subroutine kin_options_default(o)
    type(kin_options), intent(out) :: o
    integer(c_int) :: rc
    rc = kin_options_init(o, KIN_SIZEOF_OPTIONS)
  end subroutine

  subroutine kin_locate_options_default(o)
    type(kin_locate_options), intent(out) :: o
    integer(c_int) :: rc
    rc = kin_locate_options_init(o, KIN_SIZEOF_LOCATE_OPTIONS)
  end subroutine

  subroutine kin_homotopy_options_default(o)
    type(kin_homotopy_options), intent(out) :: o
    integer(c_int) :: rc
    rc = kin_homotopy_options_init(o, KIN_SIZEOF_HOMOTOPY_OPTIONS)
  end subroutine

  subroutine kin_follow_options_default(o)
    type(kin_follow_options), intent(out) :: o
    integer(c_int) :: rc
    rc = kin_follow_options_init(o, KIN_SIZEOF_FOLLOW_OPTIONS)
  end subroutine

  subroutine kin_sail_params_default(p, n_sides, n_loops)
    type(kin_sail_params), intent(out) :: p
    integer(c_int), value :: n_sides, n_loops
    integer(c_int) :: rc
    rc = kin_sail_params_init(p, KIN_SIZEOF_SAIL_PARAMS, n_sides, n_loops)
  end subroutine

  ! A NUL-terminated C string as a Fortran string ('' for a null pointer).
  function fstring(p) result(s)
    type(c_ptr), intent(in) :: p
    character(len=:), allocatable :: s
    character(kind=c_char), pointer :: chars(:)
    integer :: i, n
    if (.not. c_associated(p)) then
      s = ''
      return
    end if
    n = int(c_strlen(p))
    call c_f_pointer(p, chars, [n])
    allocate(character(len=n) :: s)
    do i = 1, n
      s(i:i) = chars(i)
    end do
  end function

  ! The message in a NUL-terminated buffer filled by C.
  function buffer_string(buf) result(s)
    character(kind=c_char), intent(in) :: buf(:)
    character(len=:), allocatable :: s
    integer :: i, n
    n = 0
    do while (n < size(buf))
      if (buf(n + 1) == c_null_char) exit
      n = n + 1
    end do
    allocate(character(len=n) :: s)
    do i = 1, n
      s(i:i) = buf(i)
    end do
  end function

  ! Version of the linked library as "MAJOR.MINOR.PATCH".
  function kin_version_string() result(s)
    character(len=:), allocatable :: s
    s = fstring(kin_version_string_c())
  end function

  ! Message of a status code ("unknown status" for unknown codes).
  function kin_strerror(status) result(s)
    integer(c_int), intent(in) :: status
    character(len=:), allocatable :: s
    s = fstring(kin_strerror_c(status))
  end function

  ! Symbolic name of a status code ("KIN_EINVAL"), or "KIN_UNKNOWN".
  function kin_status_name(status) result(s)
    integer(c_int), intent(in) :: status
    character(len=:), allocatable :: s
    s = fstring(kin_status_name_c(status))
  end function

  ! Message with detail about the last failed call on handle a ('' if none).
  function kin_last_error(a) result(s)
    type(c_ptr), intent(in) :: a
    character(len=:), allocatable :: s
    s = fstring(kin_last_error_c(a))
  end function

  ! kin_assembly_create with the sizes taken from the arrays:
  !  xyz(dim, njoints)   initial coordinates, joint by joint
  !  bars(2, nbars)      joint indices of each bar, 0-based, or 1-based
  !                      when one_based is .true.
  !  fixed(dim, njoints) optional: .true. = that coordinate is a support
  !                      (absent: every coordinate free)
  !  rest_lengths(nbars) optional: lengths to keep (absent: initial lengths)
  !  errmsg              optional: the reason of a failure ('' on success)
  ! a receives the handle (free it with kin_assembly_free), c_null_ptr on
  ! failure. Returns the C status, or KIN_ERANGE (with errmsg) when the
  ! shapes disagree: bars not 2 x nbars, fixed not shaped like xyz,
  ! rest_lengths not of size nbars.
  function kinf_create(xyz, bars, a, fixed, rest_lengths, one_based, errmsg) result(status)
    real(c_double), intent(in) :: xyz(:, :)
    integer(c_int), intent(in) :: bars(:, :)
    type(c_ptr), intent(out) :: a
    logical, intent(in), optional :: fixed(:, :)
    real(c_double), intent(in), optional :: rest_lengths(:)
    logical, intent(in), optional :: one_based
    character(len=:), allocatable, intent(out), optional :: errmsg
    integer(c_int) :: status
    integer(c_signed_char), allocatable, target :: cfixed(:, :)
    real(c_double), allocatable, target :: crest(:)
    integer(c_int), allocatable :: cbars(:, :)
    character(kind=c_char), target :: errbuf(errbuf_len)
    type(c_ptr) :: pfixed, prest
    integer(c_int) :: nbars
    a = c_null_ptr
    nbars = int(size(bars, 2), c_int)
    if (size(bars, 1) /= 2) then
      status = shape_error('kinf_create: bars must be shaped (2, nbars)')
      return
    end if
    pfixed = c_null_ptr
    if (present(fixed)) then
      if (any(shape(fixed) /= shape(xyz))) then
        status = shape_error('kinf_create: fixed must be shaped like xyz (dim, njoints)')
        return
      end if
      allocate(cfixed(size(fixed, 1), size(fixed, 2)))
      cfixed = merge(1_c_signed_char, 0_c_signed_char, fixed)
      pfixed = c_loc(cfixed)
    end if
    prest = c_null_ptr
    if (present(rest_lengths)) then
      if (size(rest_lengths) /= nbars) then
        status = shape_error('kinf_create: rest_lengths must have one entry per bar')
        return
      end if
      allocate(crest(nbars))
      crest = rest_lengths
      prest = c_loc(crest)
    end if
    allocate(cbars(2, nbars))
    cbars = bars
    if (present(one_based)) then
      if (one_based) cbars = cbars - 1
    end if
    errbuf(1) = c_null_char
    status = kin_assembly_create(int(size(xyz, 1), c_int), int(size(xyz, 2), c_int), xyz, &
                                 pfixed, nbars, cbars, prest, a, c_loc(errbuf), &
                                 int(errbuf_len, c_size_t))
    if (present(errmsg)) errmsg = buffer_string(errbuf)
  contains
    integer(c_int) function shape_error(msg)
      character(len=*), intent(in) :: msg
      if (present(errmsg)) errmsg = msg
      shape_error = KIN_ERANGE
    end function
  end function

  ! Bars into bars(2, nbars) (extra columns untouched), 0-based, or 1-based
  ! when one_based is .true. Returns KIN_OK, KIN_ENULL, or KIN_ERANGE when
  ! bars is not 2 x (at least nbars).
  function kinf_get_bars(a, bars, one_based) result(status)
    type(c_ptr), intent(in) :: a
    integer(c_int), intent(inout) :: bars(:, :)
    logical, intent(in), optional :: one_based
    integer(c_int) :: status
    integer(c_int), allocatable :: cbars(:, :)
    integer :: nbars
    nbars = kin_nbars(a)
    if (nbars < 0) then
      status = KIN_ENULL
      return
    end if
    if (size(bars, 1) /= 2 .or. size(bars, 2) < nbars) then
      status = KIN_ERANGE
      return
    end if
    allocate(cbars(2, nbars))
    status = kin_get_bars(a, cbars)
    if (status /= KIN_OK) return
    if (present(one_based)) then
      if (one_based) cbars = cbars + 1
    end if
    bars(:, 1:nbars) = cbars
  end function

  ! Supports as logicals into fixed(dim, njoints). Returns KIN_OK, KIN_ENULL,
  ! or KIN_ERANGE when fixed is not shaped (dim, njoints).
  function kinf_get_fixed(a, fixed) result(status)
    type(c_ptr), intent(in) :: a
    logical, intent(out) :: fixed(:, :)
    integer(c_int) :: status
    integer(c_signed_char), allocatable :: cfixed(:, :)
    integer :: dim, njoints
    fixed = .false.
    dim = kin_dim(a)
    njoints = kin_njoints(a)
    if (dim < 0) then
      status = KIN_ENULL
      return
    end if
    if (size(fixed, 1) /= dim .or. size(fixed, 2) /= njoints) then
      status = KIN_ERANGE
      return
    end if
    allocate(cfixed(dim, njoints))
    status = kin_get_fixed(a, cfixed)
    if (status == KIN_OK) fixed = cfixed /= 0
  end function

  ! kin_free_index with 1-based numbering when one_based is .true.: joint
  ! 1..njoints, axis 1..dim (1 = x), result 1..nfree, or 0 when the
  ! coordinate is fixed or the arguments are out of range. Without
  ! one_based, exactly kin_free_index (0-based, -1).
  function kinf_free_index(a, joint, axis, one_based) result(row)
    type(c_ptr), intent(in) :: a
    integer(c_int), intent(in) :: joint, axis
    logical, intent(in), optional :: one_based
    integer(c_int) :: row
    logical :: one
    one = .false.
    if (present(one_based)) one = one_based
    if (one) then
      row = kin_free_index(a, joint - 1, axis - 1) + 1
    else
      row = kin_free_index(a, joint, axis)
    end if
  end function

  ! kin_model_sail with the loop widths as an array (optional: absent means
  ! p%widths, usually c_null_ptr = the default widths) and the reason of a
  ! failure in errmsg. p itself is not changed.
  function kinf_model_sail(p, a, widths, errmsg) result(status)
    type(kin_sail_params), intent(in) :: p
    type(c_ptr), intent(out) :: a
    real(c_double), intent(in), optional :: widths(:)
    character(len=:), allocatable, intent(out), optional :: errmsg
    integer(c_int) :: status
    type(kin_sail_params) :: q
    real(c_double), allocatable, target :: w(:)
    character(kind=c_char), target :: errbuf(errbuf_len)
    a = c_null_ptr
    q = p
    if (present(widths)) then
      if (size(widths) /= p%n_loops) then
        if (present(errmsg)) errmsg = 'kinf_model_sail: widths must have n_loops entries'
        status = KIN_ERANGE
        return
      end if
      allocate(w(size(widths)))
      w = widths
      q%widths = c_loc(w)
    end if
    errbuf(1) = c_null_char
    status = kin_model_sail(q, a, c_loc(errbuf), int(errbuf_len, c_size_t))
    if (present(errmsg)) errmsg = buffer_string(errbuf)
  end function

  ! A Fortran string as a NUL-terminated C string (trailing blanks kept:
  ! trim the argument if they are padding).
  function cstring(s) result(c)
    character(len=*), intent(in) :: s
    character(kind=c_char), allocatable :: c(:)
    integer :: i
    allocate(c(len(s) + 1))
    do i = 1, len(s)
      c(i) = s(i:i)
    end do
    c(len(s) + 1) = c_null_char
  end function

  ! kin_assembly_load with a Fortran file name (trailing blanks dropped)
  ! and the reason of a failure in errmsg.
  function kinf_load(path, a, errmsg) result(status)
    character(len=*), intent(in) :: path
    type(c_ptr), intent(out) :: a
    character(len=:), allocatable, intent(out), optional :: errmsg
    integer(c_int) :: status
    character(kind=c_char), target :: errbuf(errbuf_len)
    errbuf(1) = c_null_char
    status = kin_assembly_load(cstring(trim(path)), a, c_loc(errbuf), int(errbuf_len, c_size_t))
    if (present(errmsg)) errmsg = buffer_string(errbuf)
  end function

  ! kin_assembly_load_string from a Fortran string (all of it).
  function kinf_load_string(text, a, errmsg) result(status)
    character(len=*), intent(in) :: text
    type(c_ptr), intent(out) :: a
    character(len=:), allocatable, intent(out), optional :: errmsg
    integer(c_int) :: status
    character(kind=c_char), target :: errbuf(errbuf_len)
    errbuf(1) = c_null_char
    status = kin_assembly_load_string(text, int(len(text), c_size_t), a, c_loc(errbuf), &
                                      int(errbuf_len, c_size_t))
    if (present(errmsg)) errmsg = buffer_string(errbuf)
  end function

  ! kin_assembly_save with a Fortran file name (trailing blanks dropped), an
  ! optional model name and the reason of a failure in errmsg.
  function kinf_save(a, path, name, errmsg) result(status)
    type(c_ptr), intent(in) :: a
    character(len=*), intent(in) :: path
    character(len=*), intent(in), optional :: name
    character(len=:), allocatable, intent(out), optional :: errmsg
    integer(c_int) :: status
    character(kind=c_char), allocatable, target :: cname(:)
    character(kind=c_char), target :: errbuf(errbuf_len)
    type(c_ptr) :: pname
    pname = c_null_ptr
    if (present(name)) then
      cname = cstring(name)
      pname = c_loc(cname)
    end if
    errbuf(1) = c_null_char
    status = kin_assembly_save(a, pname, cstring(trim(path)), c_loc(errbuf), &
                               int(errbuf_len, c_size_t))
    if (present(errmsg)) errmsg = buffer_string(errbuf)
  end function

  ! kin_assembly_save_string into a Fortran string ('' on failure); the C
  ! string is released here.
  function kinf_save_string(a, text, name, errmsg) result(status)
    type(c_ptr), intent(in) :: a
    character(len=:), allocatable, intent(out) :: text
    character(len=*), intent(in), optional :: name
    character(len=:), allocatable, intent(out), optional :: errmsg
    integer(c_int) :: status
    character(kind=c_char), allocatable, target :: cname(:)
    character(kind=c_char), target :: errbuf(errbuf_len)
    type(c_ptr) :: pname, ctext
    integer(c_size_t) :: n
    pname = c_null_ptr
    if (present(name)) then
      cname = cstring(name)
      pname = c_loc(cname)
    end if
    errbuf(1) = c_null_char
    ctext = c_null_ptr
    status = kin_assembly_save_string(a, pname, ctext, n, c_loc(errbuf), int(errbuf_len, c_size_t))
    text = fstring(ctext)
    call kin_free_string(ctext)
    if (present(errmsg)) errmsg = buffer_string(errbuf)
  end function

end module libkin
