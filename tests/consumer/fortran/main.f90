! Downstream Fortran consumer: links the installed libkin through module
! libkin, checks the module's and the library's versions agree and that the
! three-bar analysis works.
program consumer_fortran
  use, intrinsic :: iso_c_binding
  use libkin
  implicit none
  type(c_ptr) :: a
  type(kin_analysis) :: an
  if (kin_version_number() /= KIN_MODULE_VERSION_NUMBER) then
    print '(a,i0,a,i0)', 'version mismatch: module ', KIN_MODULE_VERSION_NUMBER, ', library ', &
      kin_version_number()
    error stop 1
  end if
  if (kin_model_threebar(KIN_THREEBAR_RC, a) /= KIN_OK) error stop 1
  if (kin_analyse(a, an) /= KIN_OK) error stop 1
  print '(3a,3(a,i0))', 'consumer_fortran: libkin ', kin_version_string(), ',', ' r=', an%rank, &
    ' m=', an%m, ' s=', an%s
  call kin_assembly_free(a)
  if (an%rank /= 2 .or. an%m /= 2 .or. an%s /= 1) error stop 1
end program consumer_fortran
