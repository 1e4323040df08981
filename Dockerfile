# PAL Trainer server: `paltrainer serve` on 0.0.0.0:8000, data (SQLite file, secret key) in the volume /data.
# Several replicas of this image (docs/deploy.md): the same DATABASE_URL, PALTRAINER_SECRET_KEY and REDIS_URL
# for all, and each its own REPLICA_ID (the load balancer routes the 3D view by it; Kubernetes: the pod's name);
# `paltrainer admin migrate` once before they start.

# The editor bundle (CodeMirror 6 by esbuild) → /server/static/app.js, Swagger UI's files → /server/static/swagger
FROM node:20-slim AS web
WORKDIR /web
COPY web/package.json web/package-lock.json ./
RUN npm ci --no-audit --no-fund
COPY web/src ./src
COPY web/scripts ./scripts
RUN mkdir -p /server/static && npm run build

FROM python:3.11-slim

ENV PYTHONDONTWRITEBYTECODE=1 \
    PYTHONUNBUFFERED=1 \
    PIP_NO_CACHE_DIR=1 \
    PALTRAINER_DATA_DIR=/data \
    PALTRAINER_EXERCISES_DIR=/app/exercises

WORKDIR /app
# Pango, HarfBuzz and fonts for WeasyPrint (the PDF task sheets)
RUN apt-get update \
    && apt-get install -y --no-install-recommends libpango-1.0-0 libpangoft2-1.0-0 libharfbuzz-subset0 fonts-dejavu-core \
    && rm -rf /var/lib/apt/lists/*
COPY pyproject.toml README.md ./
COPY core ./core
COPY server ./server
COPY exercises ./exercises
COPY --from=web /server/static/app.js ./server/static/app.js
COPY --from=web /server/static/swagger ./server/static/swagger
COPY --from=web /server/static/licenses.txt /server/static/licenses.json ./server/static/
RUN pip install --no-cache-dir . \
    && useradd --system --uid 10001 --home-dir /app paltrainer \
    && mkdir -p /data && chown paltrainer /data

USER paltrainer
VOLUME ["/data"]
EXPOSE 8000
HEALTHCHECK --interval=30s --timeout=5s --start-period=30s \
    CMD ["python", "-c", "import urllib.request; urllib.request.urlopen('http://127.0.0.1:8000/readyz', timeout=4)"]
CMD ["paltrainer", "serve", "--host", "0.0.0.0", "--port", "8000", "--proxy-headers"]
