"""The Dashboard tab: the motor table, the plots, the event log, recordings and the join QR code."""
