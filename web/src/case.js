// One corpus case in 3D (`cullproof corpus show ID --html`).
