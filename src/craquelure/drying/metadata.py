"""CF metadata of the drying paste (reduced units of rho0, lambda and eta): title, references and
the long name and units of each variable, read by :func:`craquelure.cf.apply`."""

from craquelure.cf import ModelMetadata

_TIME_DRYING = "eta/lambda"
_LENGTH_DRYING = "eta/sqrt(rho0 lambda)"
_AREA_DRYING = "(eta/sqrt(rho0 lambda))^2"

METADATA = ModelMetadata(
    title="Drying paste: 2D SPH of a thin visco-elastic layer under a drying stress, cracks by "
          "particle removal",
    references="the drying-paste SPH paper, arXiv:1209.6114 (equations reconstructed in the "
               "project spec ../shared/spec/drying.md)",
    reduced_unit_system="nondimensionalised by rho0, lambda and eta (drying spec section 1): "
                        f"stress lambda, time {_TIME_DRYING}, length {_LENGTH_DRYING} "
                        "(written 'length'), velocity sqrt(lambda/rho0), density rho0",
    variables={
        # campaign / fragments / thickness / accuracy datasets
        "time": ("snapshot time", _TIME_DRYING),
        "step_time": ("time-series sample time", _TIME_DRYING),
        "mass": ("particle mass", "rho0 length^2"),
        "seed": ("random seed of the sample", "1"),
        "bin": ("histogram bin index", "1"),
        "area_lo": ("lower edge of the fragment-area bin", _AREA_DRYING),
        "area_hi": ("upper edge of the fragment-area bin", _AREA_DRYING),
        "x_lo": ("lower edge of the scaled-area bin X = S/<S>_t", "1"),
        "x_hi": ("upper edge of the scaled-area bin X = S/<S>_t", "1"),
        "n_fragments": ("number of fragments", "1"),
        "total_area": ("total fragment area of the sample", _AREA_DRYING),
        "sample_mean_area": ("mean fragment area of the sample", _AREA_DRYING),
        "paste_fraction": ("fraction of paste mesh points", "1"),
        "first_removal_time": ("time of the first particle removal", _TIME_DRYING),
        "kappa_max": ("median of max_I sigma_bar_I / F before the first removal", "1"),
        "kappa_criterion": ("median of max_I s_I / F (criterion stress s) before the first "
                            "removal", "1"),
        "predicted_first_removal_time": ("t*/kappa_criterion", _TIME_DRYING),
        "damage": ("removed-area fraction d", "1"),
        "crack_length_per_area": ("crack length per area", "1/length"),
        "largest_fragment_fraction": ("largest fragment's area fraction m_max = S_max/L^2", "1"),
        "n_fragments_open": ("fragments without periodic wrap-around", "1"),
        "mean_area": ("mean fragment area <S>_t", _AREA_DRYING),
        "mean_area_se": ("standard error of <S>_t over seeds", _AREA_DRYING),
        "inverse_mean_area": ("1/<S>_t", "(eta/sqrt(rho0 lambda))^-2"),
        "inverse_mean_area_se": ("standard error of 1/<S>_t", "(eta/sqrt(rho0 lambda))^-2"),
        "n_fragments_mean": ("mean number of fragments per sample", "1"),
        "n_fragments_se": ("standard error of the number of fragments", "1"),
        "unbroken_fraction": ("fraction of samples still one fragment", "1"),
        "size_density": ("P(S;t), pooled over seeds", "(eta/sqrt(rho0 lambda))^-2"),
        "size_in_range_fraction": ("fraction of fragments with S <= S_max", "1"),
        "scaled_density": ("scaled distribution <S>_t P(X <S>_t; t)", "1"),
        "fragment_area": ("fragment area S", _AREA_DRYING),
        "fragment_scaled_area": ("X = S/<S>_t", "1"),
        "fragment_time": ("snapshot time of the fragment", _TIME_DRYING),
        "fragment_time_index": ("index of the snapshot on dim time", "1"),
        "fragment_time_index_open": ("index of the snapshot on dim time (open-image "
                                     "labelling)", "1"),
        "fragment_seed": ("random seed of the fragment's sample", "1"),
        "n_alive": ("particles not removed", "1"),
        "integrator": ("time integrator", None),
        "dt": ("time step", _TIME_DRYING),
        "dt_pair": ("index of the pair of consecutive time steps", "1"),
        "error": ("relative L2 error of the final velocity field vs the reference", "1"),
        "wall_time": ("wall time of the stepping loop", "s"),
        "rate_evaluations": ("rate-function evaluations", "1"),
        "observed_order": ("log(e_j/e_j+1)/log(dt_j/dt_j+1)", "1"),
        "tolerance": ("rkc2 local error tolerance (units of sigma_Y)", "1"),
        "rkc2_error": ("relative L2 error of the final velocity field vs the reference, rkc2 "
                       "error-controlled", "1"),
        "rkc2_wall_time": ("wall time of the stepping loop, rkc2", "s"),
        "rkc2_rate_evaluations": ("rate-function evaluations, rkc2", "1"),
        "thickness": ("layer thickness H", _LENGTH_DRYING),
        "n_seeds": ("seeds per thickness", "1"),
        "all_broken": ("1 if every sample has >= 2 fragments", "1"),
        "usable": ("1 if every thickness has every sample broken", "1"),
        "exponent": ("beta_t: slope of log <S> against log H", "1"),
        "late": ("1 if usable and in the last third of the run", "1"),
        # drying-speed study (craquelure.drying.speed): times in units of t*, slopes of b*
        "speed": ("Pi = tau/t*, tau = eta/(2 mu)", "1"),
        "fixed_time": ("t/t*", "1"),
        "t_star": ("t* = sigma_Y/v_r", _TIME_DRYING),
        "drying_rate": ("drying rate v_r", "lambda^2/eta"),
        **{f"{base}{end}": (f"{base.replace('_', ' ')}, in t*", "1")
           for base in ("first_removal_earliest", "first_removal_median", "first_sample_broken",
                        "half_samples_broken", "all_samples_broken", "t0_over_t_star")
           for end in ("", "_lo", "_hi")},
        **{f"b_over_b_star{end}": ("slope b of 1/<S>_t, in b*", "1") for end in ("", "_lo", "_hi")},
    },
)
