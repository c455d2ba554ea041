"""sweep: a matrix of bullet_sim scenarios run as Ray tasks, gathered into one table and a summary picture."""
