# ctest labels by module, so that one module's tests run alone: `ctest --preset release -L hybrid` (also
# engine, impacts, saltation, ripples, validation, io; `-L mpi` for the runs over several ranks, `-LE mpi`
# without them). Each test gets the first module whose pattern its name matches. tests/CMakeLists.txt
# labels its command-line tests with this at configure time, and ctest the tests GoogleTest discovered
# (`grainlab_tests_TESTS`) when it reads them.
function(grainlab_label_tests)
  set(modules
    hybrid "Hybrid|LammelSplash|RecordedSplash|SurfaceLayer|BedRelief|FocalPoint|ImpactSlopes|RippleCrests|RippleComposite"
    ripples "^(Worm|TriangleCollision|LimitingWavelength|Continuum|BinModel|SurfaceAnalysis|Lattice)|Ripple|LatticeAtRest|Worms|Triangles"
    saltation "^(Conveyor|WindModel|FluxGrowth|ClassicFluxLaws|CleanWindHeights|Transient|WindScene|Fluid|WindEngine)\\.|Saltation|Conveyor"
    impacts "^(ReboundModel|TwoBodyInversion|BedSurface|ImpactBed|Layering|Assemblies3d)\\.|Impact|Splash|SandGun|ActiveZone"
    validation "^(Validate|Cost|DieModel|Ensemble|LoadedDie3d|Table21|SpinningCircle|Conservation|Sorting|TumblingPolygon|PairImpact|AccuracyCost|ReportPart)\\.|Validate"
    io "^(Fuzz|GridFrameFuzz|Checkpoint|RunWriter|OutputPath|ProgressBar|PlotScript|Docs|Data)\\.|^Command\\.(Stopped|EveryNumeric|BadInput|ExistingOutput|StopAfterFrame|Inspect)"
    engine ".")
  foreach(test IN LISTS ARGN)
    set(labels "")
    set(rest ${modules})
    while(rest)
      list(POP_FRONT rest name pattern)
      if(test MATCHES "${pattern}")
        set(labels ${name})
        break()
      endif()
    endwhile()
    set(procs 1)
    if(CMAKE_SOURCE_DIR)  # at configure time: a test that holds several cores starts several ranks
      get_test_property("${test}" PROCESSORS procs)
    endif()
    if(test MATCHES "Rank|Mpirun|Decomposition|SameOnTwo" OR procs GREATER 1)
      list(APPEND labels mpi)
    endif()
    set_tests_properties("${test}" PROPERTIES LABELS "${labels}")
  endforeach()
endfunction()
