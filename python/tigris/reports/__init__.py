"""The reports layer: the paper's claims measured from sweep CSVs (report), the paper's figures
(plots, with figure_truth's checks that a figure reads true), the design variants and their
robustness matrix (variants), and an odometry run's figures (odometry_plots)."""
